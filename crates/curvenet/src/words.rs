//! The library's words for what a user set: each option by a neutral key ([`Opt`]), and
//! messages ([`Message`]) that name options by key, not by any front end's spelling.
//!
//! The rule: no message of the library spells a front end's option (`--max-gap` is the
//! command line's, `max_gap=` Python's, `"max_gap"` the server's JSON). A message names the
//! option with a [`Piece::Opt`] (the option alone) or a [`Piece::Given`] (the option with the
//! value the user gave), and each front end renders it with its own [`Wording`]; `Display`
//! renders the neutral key. A test (`tests/no_flags.rs`) reads the library's sources and
//! refuses string literals that spell a command-line flag.
//!
//! What the library records (a run folder's `result.json`, the JSON of an analysis) is read by
//! every front end alike, so its messages keep one spelling there, [`Recorded`]; a message
//! read back ([`Message::from_recorded`]) names its options again.
//!
//! Written here rather than taken from a crate: message catalogues (fluent, gettext) translate
//! whole sentences; what is needed is one sentence with option names spelled three ways.

use std::fmt;

macro_rules! options {
    ($($(#[$doc:meta])* $name:ident = $key:literal,)*) => {
        /// An option a user sets, by its neutral key (the command line's long name with `-`
        /// as `_`, Python's keyword argument, the server's JSON field).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Opt {
            $($(#[$doc])* $name,)*
        }

        impl Opt {
            /// Every option, in declaration order.
            pub const ALL: &'static [Opt] = &[$(Opt::$name,)*];

            /// The neutral key: `max_gap`.
            pub const fn key(self) -> &'static str {
                match self {
                    $(Opt::$name => $key,)*
                }
            }
        }
    };
}

options! {
    /// The surface mesh.
    Mesh = "mesh",
    /// The curve files (or arrays).
    Curves = "curves",
    /// The scale applied to the inputs.
    Scale = "scale",
    /// The target edge length.
    EdgeLength = "edge_length",
    /// The supports of open curves.
    Supports = "supports",
    /// The supports file (supports per curve end).
    SupportsFile = "supports_file",
    /// The rod radius.
    Radius = "radius",
    /// Young's modulus.
    Young = "young",
    /// The anchor weight.
    AnchorWeight = "anchor_weight",
    /// The number of eigenvalues reported.
    EigenCount = "eigen_count",
    /// Merging close joints.
    MergeJoints = "merge_joints",
    /// What the searches maximise.
    Objective = "objective",
    /// The scene's length unit.
    Units = "units",
    /// The material preset.
    Material = "material",
    /// The density.
    Density = "density",
    /// The strength.
    Strength = "strength",
    /// A tube section.
    Tube = "tube",
    /// The worst-case load's intensity.
    Load = "load",
    /// Gravity.
    Gravity = "gravity",
    /// The load cases' file.
    Loads = "loads",
    /// The load cases' deflection limit.
    DeflectionLimit = "deflection_limit",
    /// The smallest acceptable critical load factor.
    BucklingFactor = "buckling_factor",
    /// The budget as a fraction.
    Budget = "budget",
    /// The budget as a length.
    BudgetLength = "budget_length",
    /// Curves never removed.
    Keep = "keep",
    /// Curves removed before an analysis.
    Remove = "remove",
    /// Groups of curves.
    Groups = "groups",
    /// Symmetry.
    Symmetry = "symmetry",
    /// One connected structure.
    Connected = "connected",
    /// The fewest curves.
    MinCurves = "min_curves",
    /// The largest gap of the surface.
    MaxGap = "max_gap",
    /// The largest deviation of the equilibrium.
    MaxDeviation = "max_deviation",
    /// The local search after the greedy.
    LocalSearch = "local_search",
    /// Alternatives to the answer.
    Alternatives = "alternatives",
    /// The certificate.
    Certify = "certify",
    /// The certificate's branch and bound nodes.
    CertificateNodes = "certificate_nodes",
    /// Sliding the chosen curves on the surface.
    Slide = "slide",
    /// How far sliding may move a curve.
    MaxMove = "max_move",
    /// Curve ends stay where they are while sliding.
    FixedEnds = "fixed_ends",
    /// Curves sliding leaves where they are.
    Pin = "pin",
    /// Rounds of sliding and local search.
    SlideRounds = "slide_rounds",
    /// The run folder.
    Out = "out",
    /// Continuing an interrupted run.
    Resume = "resume",
    /// Running into a foreign folder.
    Force = "force",
    /// The folder of the paper's data.
    Data = "data",
    /// The folder whose run folders a server may load.
    Runs = "runs",
    /// The address a server listens on.
    Host = "host",
    /// The port a server listens on.
    Port = "port",
}

/// How a front end spells an option (with or without the value the user gave).
pub trait Wording {
    /// The option alone: `--max-gap`, `max_gap=`.
    fn option(&self, opt: Opt) -> String;
    /// The option with the value given: `--max-gap 900`, `max_gap=900`.
    fn given(&self, opt: Opt, value: &str) -> String {
        format!("{} {value}", self.option(opt))
    }
}

/// The neutral spelling: the key (`max_gap`, `max_gap 900`), what `Display` shows.
#[derive(Clone, Copy, Debug, Default)]
pub struct Neutral;

impl Wording for Neutral {
    fn option(&self, opt: Opt) -> String {
        opt.key().to_string()
    }
}

/// How the library's records spell options: a run folder's `result.json` (the build's
/// warnings, why a run has no answer) is read back by every front end alike, so its messages
/// keep one spelling, the long option of the key (`--max-gap`, `-` for `_`), which those files
/// have always held. A message read back from a record ([`Message::from_recorded`]) names its
/// options again, for each front end to spell its own way.
#[derive(Clone, Copy, Debug, Default)]
pub struct Recorded;

impl Wording for Recorded {
    fn option(&self, opt: Opt) -> String {
        format!("--{}", opt.key().replace('_', "-"))
    }
}

/// One piece of a [`Message`].
#[derive(Clone, Debug, PartialEq)]
pub enum Piece {
    /// Text as it is.
    Text(String),
    /// An option named alone.
    Opt(Opt),
    /// An option with the value the user gave.
    Given(Opt, String),
}

impl From<&str> for Piece {
    fn from(s: &str) -> Self {
        Piece::Text(s.to_string())
    }
}

impl From<String> for Piece {
    fn from(s: String) -> Self {
        Piece::Text(s)
    }
}

impl From<&String> for Piece {
    fn from(s: &String) -> Self {
        Piece::Text(s.clone())
    }
}

impl From<Opt> for Piece {
    fn from(o: Opt) -> Self {
        Piece::Opt(o)
    }
}

/// An option with the value the user gave, as a message piece: `given(Opt::MaxGap, 900)`.
pub fn given(opt: Opt, value: impl fmt::Display) -> Piece {
    Piece::Given(opt, value.to_string())
}

impl Opt {
    /// The option of a neutral key (`max_gap`), if any.
    pub fn from_key(key: &str) -> Option<Opt> {
        Opt::ALL.iter().copied().find(|o| o.key() == key)
    }
}

impl Piece {
    /// What this piece names with `value` after it: an option with the value given
    /// ([`Piece::Given`]), or text followed by a space and the value (a file's field:
    /// `"material"."young" "7GPa"`).
    pub fn with_value(&self, value: impl fmt::Display) -> Piece {
        match self {
            Piece::Opt(o) | Piece::Given(o, _) => given(*o, value),
            Piece::Text(t) => Piece::Text(format!("{t} {value}")),
        }
    }
}

/// A message for a user that may name options: text and option pieces, rendered by a front
/// end's [`Wording`] ([`Message::render`]) or neutrally (`Display`). In a record (serde) it is
/// its text in the [`Recorded`] spelling; two messages are equal when they read alike there.
#[derive(Clone, Debug, Default)]
pub struct Message(Vec<Piece>);

impl PartialEq for Message {
    fn eq(&self, other: &Self) -> bool {
        self.render(&Recorded) == other.render(&Recorded)
    }
}

impl serde::Serialize for Message {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.render(&Recorded))
    }
}

impl<'de> serde::Deserialize<'de> for Message {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = <std::borrow::Cow<'de, str>>::deserialize(d)?;
        Ok(Message::from_recorded(&text))
    }
}

impl Message {
    /// The message of `pieces`, in order.
    pub fn new(pieces: Vec<Piece>) -> Self {
        Message(pieces)
    }

    /// The pieces, in order.
    pub fn pieces(&self) -> &[Piece] {
        &self.0
    }

    /// A message as a record holds it ([`Recorded`]: `--max-gap`), its options named again.
    pub fn from_recorded(text: &str) -> Self {
        let mut pieces = Vec::new();
        let mut plain = String::new();
        let mut rest = text;
        while let Some(at) = rest.find("--") {
            let (before, from) = rest.split_at(at);
            let word_len = from[2..]
                .find(|c: char| !(c.is_ascii_lowercase() || c == '-'))
                .unwrap_or(from.len() - 2);
            let word = from[2..2 + word_len].trim_end_matches('-');
            let starts_word = !before
                .chars()
                .next_back()
                .is_some_and(|c| c == '-' || c.is_alphanumeric());
            match Opt::from_key(&word.replace('-', "_")).filter(|_| starts_word) {
                Some(opt) => {
                    plain.push_str(before);
                    if !plain.is_empty() {
                        pieces.push(Piece::Text(std::mem::take(&mut plain)));
                    }
                    pieces.push(Piece::Opt(opt));
                    rest = &from[2 + word.len()..];
                }
                None => {
                    plain.push_str(&rest[..at + 2]);
                    rest = &from[2..];
                }
            }
        }
        plain.push_str(rest);
        if !plain.is_empty() {
            pieces.push(Piece::Text(plain));
        }
        Message(pieces)
    }

    /// The options the message names.
    pub fn options(&self) -> impl Iterator<Item = Opt> + '_ {
        self.0.iter().filter_map(|p| match p {
            Piece::Opt(o) | Piece::Given(o, _) => Some(*o),
            Piece::Text(_) => None,
        })
    }

    /// The message spelled by `words`.
    pub fn render(&self, words: &dyn Wording) -> String {
        let mut s = String::new();
        for p in &self.0 {
            match p {
                Piece::Text(t) => s.push_str(t),
                Piece::Opt(o) => s.push_str(&words.option(*o)),
                Piece::Given(o, v) => s.push_str(&words.given(*o, v)),
            }
        }
        s
    }

    /// This message with `pieces` in front.
    pub fn prefixed(mut self, pieces: impl IntoIterator<Item = Piece>) -> Self {
        let mut all: Vec<Piece> = pieces.into_iter().collect();
        all.append(&mut self.0);
        Message(all)
    }

    /// `messages` one after the other, `separator` between them.
    pub fn join(messages: impl IntoIterator<Item = Message>, separator: &str) -> Self {
        let mut all = Vec::new();
        for (i, m) in messages.into_iter().enumerate() {
            if i > 0 {
                all.push(Piece::Text(separator.to_string()));
            }
            all.extend(m.0);
        }
        Message(all)
    }

    /// This message with `pieces` after it.
    pub fn then(mut self, pieces: impl IntoIterator<Item = Piece>) -> Self {
        self.0.extend(pieces);
        self
    }
}

/// A message's pieces, in order: `a.then(b)` appends message `b` to `a`.
impl IntoIterator for Message {
    type Item = Piece;
    type IntoIter = std::vec::IntoIter<Piece>;

    fn into_iter(self) -> Self::IntoIter {
        self.0.into_iter()
    }
}

impl From<String> for Message {
    fn from(s: String) -> Self {
        Message(vec![Piece::Text(s)])
    }
}

impl From<&str> for Message {
    fn from(s: &str) -> Self {
        Message(vec![Piece::Text(s.to_string())])
    }
}

impl fmt::Display for Message {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(&Neutral))
    }
}

impl std::error::Error for Message {}

/// A [`Message`] from pieces: text (`&str`, `String`), options ([`Opt`]) and options with
/// their values ([`given`]): `message!["give ", Opt::EdgeLength, " or another ", Opt::Scale]`.
#[macro_export]
macro_rules! message {
    ($($piece:expr),* $(,)?) => {
        $crate::words::Message::new(vec![$($crate::words::Piece::from($piece)),*])
    };
}

pub use crate::message;

#[cfg(test)]
mod tests {
    use super::*;

    struct Flags;
    impl Wording for Flags {
        fn option(&self, opt: Opt) -> String {
            format!("--{}", opt.key().replace('_', "-"))
        }
    }

    #[test]
    fn a_message_names_options_in_each_front_ends_words() {
        let m = message![
            given(Opt::EdgeLength, 0.5),
            ": too small; give a larger ",
            Opt::EdgeLength,
            " or another ",
            Opt::Scale
        ];
        assert_eq!(
            m.render(&Flags),
            "--edge-length 0.5: too small; give a larger --edge-length or another --scale"
        );
        assert_eq!(
            m.to_string(),
            "edge_length 0.5: too small; give a larger edge_length or another scale"
        );
        assert_eq!(
            m.options().collect::<Vec<_>>(),
            [Opt::EdgeLength, Opt::EdgeLength, Opt::Scale]
        );
    }

    #[test]
    fn a_record_reads_back_with_its_options() {
        let m = message![
            "the edge is short (consider ",
            Opt::MergeJoints,
            "); ",
            given(Opt::MaxGap, 900),
            " --- --nothing-known a--b"
        ];
        let text = m.render(&Recorded);
        assert_eq!(
            text,
            "the edge is short (consider --merge-joints); --max-gap 900 --- --nothing-known a--b"
        );
        let back = Message::from_recorded(&text);
        assert_eq!(back.render(&Recorded), text);
        assert_eq!(back, m);
        assert_eq!(
            back.options().collect::<Vec<_>>(),
            [Opt::MergeJoints, Opt::MaxGap]
        );
        assert_eq!(
            back.render(&Flags),
            "the edge is short (consider --merge-joints); --max-gap 900 --- --nothing-known a--b"
        );
        assert_eq!(
            back.to_string(),
            "the edge is short (consider merge_joints); max_gap 900 --- --nothing-known a--b"
        );
        let json = serde_json::to_string(&m).unwrap();
        assert_eq!(serde_json::from_str::<Message>(&json).unwrap(), m);
    }

    #[test]
    fn keys_are_distinct_snake_case() {
        let mut keys: Vec<&str> = Opt::ALL.iter().map(|o| o.key()).collect();
        assert!(
            keys.iter()
                .all(|k| k.chars().all(|c| c.is_ascii_lowercase() || c == '_'))
        );
        keys.sort_unstable();
        let n = keys.len();
        keys.dedup();
        assert_eq!(keys.len(), n);
    }
}
