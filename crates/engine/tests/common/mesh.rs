//! Meshes shared by the engine's test crates (each includes this file by path).

/// The triangles of an `n × n`-node grid numbered row by row (node `j n + i`), each cell
/// split along alternating diagonals so that no direction is preferred.
pub fn alternating_faces(n: usize) -> Vec<[usize; 3]> {
    let id = |i: usize, j: usize| j * n + i;
    let mut faces = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                faces.extend([[a, b, c], [a, c, d]]);
            } else {
                faces.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    faces
}
