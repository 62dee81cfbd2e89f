//! Groups of curves kept or removed together: the groups file (`--groups FILE`) and the
//! groups of a JSON curve file (each curve's `"group"`).
//!
//! The groups file is plain text, one group per line:
//!
//! ```text
//! # arches of the west facade
//! west: 0 1 2 3
//! east: 4-7, 12
//! 8, 9
//! ```
//!
//! - `NAME:` is optional (a group without one is named `line N`); a name is any text without
//!   `:` or `#`, trimmed, used once per file.
//! - Curve ids are 0-based in loading order (across every curve file, then generated curves),
//!   separated by spaces and/or commas; `A-B` is the range `A..=B`.
//! - `#` starts a comment; blank lines are ignored.
//! - A curve may appear in one group of the file only; a group of one curve changes nothing.
//!
//! Every mistake is an [`InputError`] naming the file and the line: a token that is not an id
//! or a range, a range that runs backwards, a name used twice, a curve listed twice, a name
//! with no ids, and (once the network is known, [`check_groups`]) an id past the last curve.

use crate::io::InputError;
use crate::words::Message;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The longest range `A-B` accepted (a guard against `0-4000000000` eating the memory).
const MAX_RANGE: usize = 1 << 20;

/// One group: curves kept or removed together.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Group {
    /// Its name (from the file, or `line N`).
    pub name: String,
    /// Its curves, ascending, without repeats.
    pub curves: Vec<usize>,
    /// Where it was defined (`file:line`), for messages.
    pub origin: String,
}

/// Parses a groups file (see the module documentation). `file` names the input in messages.
///
/// # Errors
///
/// [`InputError::Parse`] at the offending line.
pub fn parse_groups(text: &str, file: &str) -> Result<Vec<Group>, InputError> {
    let mut groups: Vec<Group> = Vec::new();
    // Curve → (group name, line) of the group that listed it.
    let mut listed: std::collections::HashMap<usize, (String, usize)> = Default::default();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let err = |message: String| InputError::parse(file, line, message);
        let body = raw.split('#').next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let (name, ids) = match body.split_once(':') {
            Some((name, ids)) => {
                let name = name.trim();
                if name.is_empty() {
                    return Err(err("empty group name before `:`".into()));
                }
                (name.to_owned(), ids)
            }
            None => (format!("line {line}"), body),
        };
        if let Some(g) = groups.iter().find(|g| g.name == name) {
            return Err(err(format!(
                "group name `{name}` is already used ({})",
                g.origin
            )));
        }
        let mut curves = Vec::new();
        for token in ids.split(|c: char| c == ',' || c.is_whitespace()) {
            if token.is_empty() {
                continue;
            }
            parse_token(token, file, line, &mut curves)?;
        }
        if curves.is_empty() {
            return Err(err(format!("group `{name}` lists no curve ids")));
        }
        for &c in &curves {
            if let Some((other, at)) = listed.get(&c) {
                let place = if *other == name {
                    "earlier on this line".to_owned()
                } else {
                    format!("in group `{other}` (line {at})")
                };
                return Err(err(format!(
                    "curve {c} is already listed {place}: a curve belongs to one group"
                )));
            }
            listed.insert(c, (name.clone(), line));
        }
        curves.sort_unstable();
        groups.push(Group {
            name,
            curves,
            origin: format!("{file}:{line}"),
        });
    }
    Ok(groups)
}

/// One id or range token, appended to `curves`.
fn parse_token(
    token: &str,
    file: &str,
    line: usize,
    curves: &mut Vec<usize>,
) -> Result<(), InputError> {
    let err = |message: String| InputError::parse(file, line, message);
    let id = |t: &str| -> Result<usize, InputError> {
        if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) {
            return Err(err(format!(
                "`{}` is not a curve id (a number from 0) nor a range `A-B`",
                shorten(token)
            )));
        }
        t.parse::<usize>()
            .map_err(|_| err(format!("curve id `{}` is too large", shorten(t))))
    };
    match token.split_once('-') {
        None => curves.push(id(token)?),
        Some((a, b)) => {
            let (a, b) = (id(a)?, id(b)?);
            if b < a {
                return Err(err(format!("range {a}-{b} runs backwards (write {b}-{a})")));
            }
            if b - a >= MAX_RANGE {
                return Err(err(format!(
                    "range {a}-{b} is longer than any network ({MAX_RANGE} ids)"
                )));
            }
            for c in a..=b {
                if !curves.contains(&c) {
                    curves.push(c);
                }
            }
        }
    }
    Ok(())
}

/// `t`, cut to a readable length for a message.
fn shorten(t: &str) -> String {
    const MAX: usize = 24;
    if t.chars().count() <= MAX {
        t.to_owned()
    } else {
        format!("{}…", t.chars().take(MAX).collect::<String>())
    }
}

/// Reads and parses a groups file.
///
/// # Errors
///
/// [`InputError::Io`] when it cannot be read, [`InputError::Parse`] as [`parse_groups`].
pub fn read_groups(path: &Path) -> Result<Vec<Group>, InputError> {
    let file = path.display().to_string();
    let text = std::fs::read(path).map_err(|source| InputError::Io {
        file: file.clone(),
        source,
    })?;
    let text = String::from_utf8(text)
        .map_err(|_| InputError::parse(&file, 0, "the groups file is not valid UTF-8 text"))?;
    parse_groups(&text, &file)
}

/// The groups named by the curves' own tags (the `"group"` of a JSON curve file), one per
/// name, in order of their first curve. `tags[c]` is curve `c`'s tag; `origins[c]` where the
/// curve was defined (`file:line`).
pub fn groups_of_tags(tags: &[Option<String>], origins: &[String]) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    for (c, tag) in tags.iter().enumerate() {
        let Some(name) = tag else { continue };
        match groups.iter_mut().find(|g| &g.name == name) {
            Some(g) => g.curves.push(c),
            None => groups.push(Group {
                name: name.clone(),
                curves: vec![c],
                origin: origins.get(c).cloned().unwrap_or_default(),
            }),
        }
    }
    groups
}

/// Checks that every group names curves of a network of `n` curves.
///
/// # Errors
///
/// `file:line: …` naming the group and the first id past the last curve.
pub fn check_groups(groups: &[Group], n: usize) -> Result<(), Message> {
    for g in groups {
        if let Some(&c) = g.curves.iter().find(|&&c| c >= n) {
            return Err(format!(
                "{}: group `{}` names curve {c}, but the network has {n} curves (ids 0..{})",
                g.origin,
                g.name,
                n.saturating_sub(1)
            )
            .into());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str, line: usize, phrase: &str) {
        let e = parse_groups(text, "g.txt").expect_err("rejected");
        assert_eq!(e.line(), Some(line), "{e}");
        assert!(e.to_string().starts_with(&format!("g.txt:{line}: ")), "{e}");
        assert!(e.to_string().contains(phrase), "`{e}` lacks `{phrase}`");
    }

    #[test]
    fn parses_names_ranges_commas_and_comments() {
        let g = parse_groups(
            "# facade\nwest: 0 1 2 3\n\n east : 7-9, 4   # the east side\n10,11\n",
            "g.txt",
        )
        .expect("parses");
        assert_eq!(g.len(), 3);
        assert_eq!(g[0].name, "west");
        assert_eq!(g[0].curves, vec![0, 1, 2, 3]);
        assert_eq!(g[0].origin, "g.txt:2");
        assert_eq!(g[1].name, "east");
        assert_eq!(g[1].curves, vec![4, 7, 8, 9]);
        assert_eq!(g[2].name, "line 5");
        assert_eq!(g[2].curves, vec![10, 11]);
        assert!(parse_groups("", "g.txt").expect("empty is fine").is_empty());
    }

    #[test]
    fn mistakes_name_the_line() {
        err("a: 0 1\nb: 2 x\n", 2, "`x` is not a curve id");
        err("a: 0 -1\n", 1, "is not a curve id");
        err("a: 5-3\n", 1, "runs backwards");
        err("a: 0-99999999\n", 1, "longer than any network");
        err("a: 0 1\na: 2\n", 2, "`a` is already used (g.txt:1)");
        err(
            "a: 0 1\nb: 1 2\n",
            2,
            "curve 1 is already listed in group `a` (line 1)",
        );
        err("a: 0 1 1\n", 1, "earlier on this line");
        err("a:\n", 1, "lists no curve ids");
        err(": 1 2\n", 1, "empty group name");
        err("a: 99999999999999999999999\n", 1, "too large");
    }

    #[test]
    fn ids_past_the_last_curve_are_named() {
        let g = parse_groups("\nring: 0 40\n", "g.txt").expect("parses");
        let e = check_groups(&g, 33)
            .expect_err("40 is out of range")
            .to_string();
        assert!(e.starts_with("g.txt:2: group `ring` names curve 40"), "{e}");
        assert!(e.contains("33 curves (ids 0..32)"), "{e}");
        assert!(check_groups(&g, 41).is_ok());
    }

    #[test]
    fn tags_make_one_group_per_name() {
        let tags = vec![
            Some("a".to_owned()),
            None,
            Some("b".to_owned()),
            Some("a".to_owned()),
        ];
        let origins: Vec<String> = (0..4).map(|i| format!("c.json:{}", 5 + i)).collect();
        let g = groups_of_tags(&tags, &origins);
        assert_eq!(g.len(), 2);
        assert_eq!((g[0].name.as_str(), g[0].curves.clone()), ("a", vec![0, 3]));
        assert_eq!(g[0].origin, "c.json:5");
        assert_eq!((g[1].name.as_str(), g[1].curves.clone()), ("b", vec![2]));
    }
}
