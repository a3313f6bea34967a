//! The language in which scenario keys are declared: each key is written once, in
//! [`super::sections`], with its name, Rust type, default, unit, allowed range and doc line,
//! and everything else is derived from that declaration:
//! - the serde struct field and its `Default` (`section!`);
//! - the raw-tree schema: unknown keys, "did you mean", value types ([`super::schema`]);
//! - the per-key checks: range, "only with", "required with" ([`super::validate`]);
//! - the key tables of `docs/scenarios.md` ([`super::docs`]).
//!
//! docs/architecture.md §How a scenario key flows shows a key being added.

use serde::Serialize;

/// The TOML type (and finer constraint) a key accepts, checked on the raw tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// Any string.
    Str,
    /// A finite number (integers are accepted and widened).
    Float,
    /// A non-negative integer.
    Count,
    /// `true` or `false`.
    Bool,
    /// One string of a fixed set.
    Choice(&'static [&'static str]),
    /// An array of exactly this many finite numbers (a point or a vector).
    Vector(usize),
    /// An array of finite numbers.
    FloatList,
    /// An array of non-negative integers.
    CountList,
    /// A named site set, or a non-empty array of `[x, y]` pairs.
    Sites,
}

/// A Rust type that can hold a scenario key's value: it names the TOML kind it is read from.
pub trait KeyType {
    /// The raw-tree kind.
    const KIND: Kind;
}

impl KeyType for f64 {
    const KIND: Kind = Kind::Float;
}
impl KeyType for usize {
    const KIND: Kind = Kind::Count;
}
impl KeyType for bool {
    const KIND: Kind = Kind::Bool;
}
impl KeyType for String {
    const KIND: Kind = Kind::Str;
}
impl KeyType for std::path::PathBuf {
    const KIND: Kind = Kind::Str;
}
impl<const N: usize> KeyType for [f64; N] {
    const KIND: Kind = Kind::Vector(N);
}
impl KeyType for Vec<f64> {
    const KIND: Kind = Kind::FloatList;
}
impl KeyType for Vec<usize> {
    const KIND: Kind = Kind::CountList;
}
/// An optional key: absent means "not set" (a feature off, or a default computed elsewhere).
impl<T: KeyType> KeyType for Option<T> {
    const KIND: Kind = T::KIND;
}

/// One end of a [`Range`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// No bound.
    Open,
    /// The value may equal it.
    Incl(f64),
    /// The value must differ from it.
    Excl(f64),
}

/// The interval a number key must lie in, and why (the reason is part of the message).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower end.
    pub lo: Bound,
    /// Upper end.
    pub hi: Bound,
    /// The reason, in a few words ("a length").
    pub why: &'static str,
}

impl Range {
    /// Whether `x` lies in the range.
    pub fn contains(&self, x: f64) -> bool {
        let lo = match self.lo {
            Bound::Open => true,
            Bound::Incl(a) => x >= a,
            Bound::Excl(a) => x > a,
        };
        let hi = match self.hi {
            Bound::Open => true,
            Bound::Incl(b) => x <= b,
            Bound::Excl(b) => x < b,
        };
        lo && hi
    }

    /// What the value must be, for the error message: "be positive", "be between 3 and 10".
    pub fn requirement(&self) -> String {
        use Bound::*;
        match (self.lo, self.hi) {
            (Excl(0.0), Open) => "be positive".into(),
            (Incl(0.0), Open) => "not be negative".into(),
            (Incl(a), Open) => format!("be at least {a}"),
            (Excl(a), Open) => format!("be greater than {a}"),
            (Open, Incl(b)) => format!("be at most {b}"),
            (Open, Excl(b)) => format!("be below {b}"),
            (Incl(a), Incl(b)) => format!("be between {a} and {b}"),
            (lo, hi) => format!("lie in {}", interval(lo, hi)),
        }
    }

    /// The range as the "allowed" column of the docs shows it: "> 0", "3 … 100000".
    pub fn doc(&self) -> String {
        use Bound::*;
        match (self.lo, self.hi) {
            (Open, Open) => String::new(),
            (Excl(a), Open) => format!("> {}", num(a)),
            (Incl(a), Open) => format!("≥ {}", num(a)),
            (Open, Incl(b)) => format!("≤ {}", num(b)),
            (Open, Excl(b)) => format!("< {}", num(b)),
            (Incl(a), Incl(b)) => format!("{} … {}", num(a), num(b)),
            (lo, hi) => interval(lo, hi),
        }
    }
}

/// `(a, b]`-style notation (with a true minus sign).
fn interval(lo: Bound, hi: Bound) -> String {
    let (l, a) = match lo {
        Bound::Incl(a) => ('[', num(a)),
        Bound::Excl(a) => ('(', num(a)),
        Bound::Open => ('(', "−∞".into()),
    };
    let (h, b) = match hi {
        Bound::Incl(b) => (']', num(b)),
        Bound::Excl(b) => (')', num(b)),
        Bound::Open => (')', "∞".into()),
    };
    format!("{l}{a}, {b}{h}")
}

fn num(x: f64) -> String {
    let s = format!("{x}");
    match s.strip_prefix('-') {
        Some(rest) => format!("−{rest}"),
        None => s,
    }
}

/// "Key `key` has the value `value`": a condition on another key of the resolved scenario
/// (its default counts), e.g. `time.adaptive = true` or `canopy.shape = "mesh"`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cond {
    /// Dotted key path.
    pub key: &'static str,
    /// The value, as written for a boolean or a number, unquoted for a string.
    pub value: &'static str,
}

impl Cond {
    /// Whether the resolved tree `v` of the key satisfies the condition (`None`: the key is
    /// absent, which satisfies none).
    pub fn holds(&self, v: Option<&toml::Value>) -> bool {
        match v {
            Some(toml::Value::String(s)) => s == self.value,
            Some(toml::Value::Boolean(b)) => b.to_string() == self.value,
            Some(toml::Value::Integer(i)) => i.to_string() == self.value,
            Some(toml::Value::Float(x)) => x.to_string() == self.value,
            _ => false,
        }
    }

    /// `key = value` as it would be written in the file (strings quoted).
    pub fn display(&self, kind: Option<Kind>) -> String {
        match kind {
            Some(Kind::Str | Kind::Choice(_) | Kind::Sites) => {
                format!("{} = \"{}\"", self.key, self.value)
            }
            _ => format!("{} = {}", self.key, self.value),
        }
    }
}

/// `Cond { key, value }`, for declarations.
pub const fn when(key: &'static str, value: &'static str) -> Cond {
    Cond { key, value }
}

/// Everything declared about a key besides its name, type and default. Built with
/// [`key`] and the chained `const fn`s below.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key {
    /// SI unit ("–" when dimensionless).
    pub unit: &'static str,
    /// The interval a number must lie in (for a list: every element).
    pub range: Option<Range>,
    /// The range is only checked when this holds (e.g. `canopy.nodes` for a rod).
    pub range_when: Option<Cond>,
    /// The key may only be written when this holds; the text completes the message.
    pub only_with: Option<(Cond, &'static str)>,
    /// The key must be written (the reason is the message).
    pub required: Option<&'static str>,
    /// The key must be written when this holds; the text completes the message.
    pub required_with: Option<(Cond, &'static str)>,
    /// An optional key the loader fills with this value when the condition holds and the
    /// key is absent (the resolved scenario then shows it).
    pub default_with: Option<(Cond, f64)>,
    /// The "default" column when it is not the declared value itself (a context default).
    pub default_doc: Option<&'static str>,
    /// Added in parentheses after the default ("Kevlar").
    pub default_note: &'static str,
    /// Added to the "allowed" column: rules checked by hand in `validate.rs`.
    pub note: &'static str,
}

/// A key with a dimensionless value and no rules yet.
pub const fn key() -> Key {
    Key {
        unit: "–",
        range: None,
        range_when: None,
        only_with: None,
        required: None,
        required_with: None,
        default_with: None,
        default_doc: None,
        default_note: "",
        note: "",
    }
}

impl Key {
    /// SI unit.
    pub const fn unit(mut self, unit: &'static str) -> Self {
        self.unit = unit;
        self
    }
    /// Any range.
    pub const fn range(mut self, lo: Bound, hi: Bound, why: &'static str) -> Self {
        self.range = Some(Range { lo, hi, why });
        self
    }
    /// `> 0`.
    pub const fn positive(self, why: &'static str) -> Self {
        self.range(Bound::Excl(0.0), Bound::Open, why)
    }
    /// `≥ 0`.
    pub const fn non_negative(self, why: &'static str) -> Self {
        self.range(Bound::Incl(0.0), Bound::Open, why)
    }
    /// `lo ≤ x ≤ hi`.
    pub const fn between(self, lo: f64, hi: f64, why: &'static str) -> Self {
        self.range(Bound::Incl(lo), Bound::Incl(hi), why)
    }
    /// `x ≥ lo`.
    pub const fn at_least(self, lo: f64, why: &'static str) -> Self {
        self.range(Bound::Incl(lo), Bound::Open, why)
    }
    /// Check the range only when `cond` holds.
    pub const fn range_when(mut self, cond: Cond) -> Self {
        self.range_when = Some(cond);
        self
    }
    /// Refuse the key unless `cond` holds; the message reads "only used with `cond`{why}".
    pub const fn only_with(mut self, cond: Cond, why: &'static str) -> Self {
        self.only_with = Some((cond, why));
        self
    }
    /// The key must be written; `why` is the message.
    pub const fn required(mut self, why: &'static str) -> Self {
        self.required = Some(why);
        self
    }
    /// The key must be written when `cond` holds; the message reads "`cond` {why}".
    pub const fn required_with(mut self, cond: Cond, why: &'static str) -> Self {
        self.required_with = Some((cond, why));
        self
    }
    /// Filled with `value` by the loader when `cond` holds and the key is absent.
    pub const fn default_with(mut self, cond: Cond, value: f64) -> Self {
        self.default_with = Some((cond, value));
        self
    }
    /// The docs' default column, for a default that depends on other keys.
    pub const fn default_doc(mut self, text: &'static str) -> Self {
        self.default_doc = Some(text);
        self
    }
    /// A remark after the default ("Kevlar").
    pub const fn default_note(mut self, text: &'static str) -> Self {
        self.default_note = text;
        self
    }
    /// Further rules for the docs' "allowed" column, enforced by hand-written checks (each one
    /// broken by a case of `tests/scenario/notes.rs`, which fails for a note without one).
    pub const fn note(mut self, text: &'static str) -> Self {
        self.note = text;
        self
    }
}

/// One declared key.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyDecl {
    /// Name inside its section.
    pub name: &'static str,
    /// Raw-tree kind, from the field's Rust type.
    pub kind: Kind,
    /// The doc line (also the field's rustdoc).
    pub doc: &'static str,
    /// Unit, range, conditions, docs.
    pub meta: Key,
}

/// A struct generated by `section!`: its keys and defaults.
pub trait Declared: Default + Serialize {
    /// The keys, in declaration (and resolved-TOML) order.
    const KEYS: &'static [KeyDecl];
}

/// A section of the scenario file.
#[derive(Debug, Clone, Copy)]
pub struct Section {
    /// Table name; `""` for the top-level keys.
    pub name: &'static str,
    /// `[[name]]`: an array of tables, each entry with these keys (paths `name[i].key`).
    pub array: bool,
    /// The section may be left out entirely (an `Option` in [`super::Scenario`]: absent means
    /// the feature is off); its required keys are then only required when it is written.
    pub optional: bool,
    /// The keys.
    pub keys: &'static [KeyDecl],
    /// The section may only be written when this holds ("only used with `cond`{why}").
    pub only_with: Option<(Cond, &'static str)>,
    /// The declared defaults as a TOML table (for the docs).
    pub defaults: fn() -> toml::Table,
}

fn defaults_of<T: Declared>() -> toml::Table {
    toml::Table::try_from(T::default()).unwrap_or_default()
}

impl Section {
    /// A `[name]` table of `T`'s keys.
    pub const fn table<T: Declared>(name: &'static str) -> Self {
        Section {
            name,
            array: false,
            optional: false,
            keys: T::KEYS,
            only_with: None,
            defaults: defaults_of::<T>,
        }
    }
    /// A `[[name]]` array of tables, each entry of `T`'s keys.
    pub const fn array<T: Declared>(name: &'static str) -> Self {
        Section {
            array: true,
            ..Self::table::<T>(name)
        }
    }
    /// An optional `[name]` table of `T`'s keys (an `Option<T>` field of the scenario).
    pub const fn optional<T: Declared>(name: &'static str) -> Self {
        Section {
            optional: true,
            ..Self::table::<T>(name)
        }
    }
    /// Refuse the section unless `cond` holds.
    pub const fn only_with(mut self, cond: Cond, why: &'static str) -> Self {
        self.only_with = Some((cond, why));
        self
    }
    /// The declaration of key `name`.
    pub fn key(&self, name: &str) -> Option<&'static KeyDecl> {
        self.keys.iter().find(|k| k.name == name)
    }
}

/// Declare a section: a serde struct whose fields are the keys, its `Default`, and its
/// [`Declared::KEYS`]. Each field is
///
/// ```text
/// /// doc line (rustdoc and the docs table's "meaning")
/// #[serde(...)]                  // optional serde attributes of the field
/// name: Type = default => key().unit("m").positive("a length"),
/// ```
///
/// `Option<T>` fields are optional keys (absent: `None`, not written back); every other
/// field is always written to the resolved scenario.
macro_rules! section {
    (
        $(#[doc = $sdoc:literal])*
        $vis:vis struct $name:ident {
            $(
                $(#[doc = $doc:literal])+
                $(#[serde($($serde:tt)*)])*
                $field:ident : $ty:ty = $default:expr => $meta:expr,
            )*
        }
    ) => {
        $(#[doc = $sdoc])*
        #[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
        #[serde(deny_unknown_fields, default)]
        $vis struct $name {
            $(
                $(#[doc = $doc])+
                $(#[serde($($serde)*)])*
                pub $field: $ty,
            )*
        }

        impl Default for $name {
            fn default() -> Self {
                Self { $($field: $default,)* }
            }
        }

        impl $crate::scenario::keys::Declared for $name {
            const KEYS: &'static [$crate::scenario::keys::KeyDecl] = &[$(
                $crate::scenario::keys::KeyDecl {
                    name: stringify!($field),
                    kind: <$ty as $crate::scenario::keys::KeyType>::KIND,
                    doc: concat!($($doc),+),
                    meta: $meta,
                },
            )*];
        }
    };
}

/// Declare a choice key's type: an enum read from one of a fixed set of strings, with
/// `NAMES` (in declaration order) and `name()`.
///
/// ```text
/// /// doc
/// pub enum DragLaw {
///     /// doc
///     Quadratic = "quadratic",
///     /// doc
///     Linear = "linear",
/// }
/// ```
macro_rules! choice {
    (
        $(#[doc = $edoc:literal])*
        $vis:vis enum $name:ident {
            $(
                $(#[doc = $doc:literal])+
                $variant:ident = $text:literal,
            )+
        }
    ) => {
        $(#[doc = $edoc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
        $vis enum $name {
            $(
                $(#[doc = $doc])+
                #[serde(rename = $text)]
                $variant,
            )+
        }

        impl $name {
            /// Every value, as written in a scenario.
            pub const NAMES: &'static [&'static str] = &[$($text),+];

            /// This value as written in a scenario.
            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$variant => $text,)+
                }
            }
        }

        impl $crate::scenario::keys::KeyType for $name {
            const KIND: $crate::scenario::keys::Kind =
                $crate::scenario::keys::Kind::Choice(Self::NAMES);
        }
    };
}

pub(crate) use choice;
pub(crate) use section;
