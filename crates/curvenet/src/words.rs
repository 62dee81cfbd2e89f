//! The library's words for what a user set: each option by a neutral key ([`Opt`]), and
//! messages ([`Message`]) that name options by key, not by any front end's spelling.
//!
//! The rule: no message of the library spells a front end's option (`--max-gap` is the
//! command line's, `max_gap=` Python's, `"max_gap"` the server's JSON). A message names the
//! option with a [`Piece::Opt`] (the option alone) or a [`Piece::Given`] (the option with the
//! value the user gave), and each front end renders it with its own [`Wording`]; `Display`
//! renders the neutral key. A test reads the library's sources and refuses string literals
//! that spell a command-line flag.
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
    /// The run folder.
    Out = "out",
    /// Continuing an interrupted run.
    Resume = "resume",
    /// Running into a foreign folder.
    Force = "force",
    /// The folder of the paper's data.
    Data = "data",
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

/// A message for a user that may name options: text and option pieces, rendered by a front
/// end's [`Wording`] ([`Message::render`]) or neutrally (`Display`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Message(Vec<Piece>);

impl Message {
    /// The message of `pieces`, in order.
    pub fn new(pieces: Vec<Piece>) -> Self {
        Message(pieces)
    }

    /// The pieces, in order.
    pub fn pieces(&self) -> &[Piece] {
        &self.0
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

    /// This message with `pieces` after it.
    pub fn then(mut self, pieces: impl IntoIterator<Item = Piece>) -> Self {
        self.0.extend(pieces);
        self
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
