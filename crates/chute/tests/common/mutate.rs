//! Text mutations of the property tests (scenario and mesh files): each returns the mutated
//! text; positions wrap around the text or its lines and land on character boundaries.

/// The largest character boundary of `s` at or before `i`.
pub fn floor_boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// `what` inserted at byte `pos` (wrapped).
pub fn insert(t: &str, pos: usize, what: &str) -> String {
    let i = floor_boundary(t, pos % (t.len() + 1));
    format!("{}{}{}", &t[..i], what, &t[i..])
}

/// About `len + 1` bytes deleted from byte `pos` (wrapped).
pub fn delete(t: &str, pos: usize, len: usize) -> String {
    let i = floor_boundary(t, pos % (t.len() + 1));
    let j = floor_boundary(t, i + len + 1);
    format!("{}{}", &t[..i], &t[j..])
}

/// Line `pos` (wrapped) duplicated; `lines` must not be empty.
pub fn duplicate_line(mut lines: Vec<String>, pos: usize) -> String {
    let k = pos % lines.len();
    lines.insert(k, lines[k].clone());
    lines.join("\n")
}

/// Line `pos` (wrapped) swapped with the next; `lines` must have two or more.
pub fn swap_lines(mut lines: Vec<String>, pos: usize) -> String {
    let k = pos % (lines.len() - 1);
    lines.swap(k, k + 1);
    lines.join("\n")
}
