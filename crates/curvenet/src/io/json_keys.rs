//! Duplicate keys in a JSON object, which every JSON text the tool reads refuses.
//!
//! JSON leaves an object with a key given twice undefined, and `serde_json` takes the last one
//! silently: `{"budget": 0.1, "budget": 0.9}` would run at 0.9 whatever the author meant, and
//! a curve file edited by hand could carry two `"points"` of which one is ignored. `serde_json`
//! has no switch to refuse them, and a deserialisation wrapper would have to wrap every type
//! read (and `#[serde(flatten)]`, untagged enums and `serde_json::Value` all collect maps their
//! own way), so the text is checked on its own instead: [`duplicate_key`] walks it once, after
//! `serde_json` has accepted it (so it is valid JSON, nested at most `serde_json`'s 128
//! levels), holding no value, only the keys of the objects open at the moment, and names the
//! first key given twice, where (a path such as `curves[2].material`) and on which lines.

use std::collections::HashMap;

/// A key given twice in one object.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DuplicateKey {
    /// The key (unescaped).
    pub key: String,
    /// The object holding it, as a path from the document's root (`curves[2].material`; empty
    /// for the root object).
    pub path: String,
    /// The 1-based line of its second occurrence.
    pub line: usize,
    /// The 1-based column (in characters) of its second occurrence.
    pub column: usize,
    /// The 1-based line of its first occurrence.
    pub first_line: usize,
}

impl DuplicateKey {
    /// `duplicate key "points" in curves[2] (first at line 12)`: what a message says of it,
    /// without the line of the second occurrence (the message's own place gives it).
    pub fn describe(&self) -> String {
        let place = if self.path.is_empty() {
            String::new()
        } else {
            format!(" in {}", self.path)
        };
        format!(
            "duplicate key {:?}{place} (first at line {}): give each key once",
            self.key, self.first_line
        )
    }
}

/// The first key given twice in one object of the JSON `text`, if any. `text` is expected to be
/// JSON `serde_json` accepted; anything else ends the walk with `None` (its errors are
/// `serde_json`'s to report).
pub fn duplicate_key(text: &str) -> Option<DuplicateKey> {
    Walker {
        s: text.as_bytes(),
        text,
        i: 0,
        line: 1,
        line_start: 0,
        path: Vec::new(),
    }
    .value(0)
    .err()
    .flatten()
}

/// Deeper than this is no JSON `serde_json` accepted (its limit is 128).
const MAX_DEPTH: usize = 256;

/// One step of the path to an object: a key or an array index.
enum Step {
    Key(String),
    Index(usize),
}

struct Walker<'a> {
    s: &'a [u8],
    text: &'a str,
    i: usize,
    line: usize,
    line_start: usize,
    path: Vec<Step>,
}

/// Why the walk ended early: a duplicate found (`Some`), or text it does not follow (`None`).
type Stop = Option<DuplicateKey>;

impl Walker<'_> {
    fn skip_ws(&mut self) {
        while let Some(&c) = self.s.get(self.i) {
            match c {
                b'\n' => {
                    self.i += 1;
                    self.line += 1;
                    self.line_start = self.i;
                }
                b' ' | b'\t' | b'\r' => self.i += 1,
                _ => break,
            }
        }
    }

    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn value(&mut self, depth: usize) -> Result<(), Stop> {
        if depth > MAX_DEPTH {
            return Err(None);
        }
        self.skip_ws();
        match self.peek().ok_or(None)? {
            b'{' => self.object(depth),
            b'[' => self.array(depth),
            b'"' => self.string().map(|_| ()),
            _ => {
                // A number or a literal: up to the next delimiter.
                while let Some(c) = self.peek() {
                    if matches!(c, b',' | b'}' | b']' | b' ' | b'\t' | b'\r' | b'\n') {
                        break;
                    }
                    self.i += 1;
                }
                Ok(())
            }
        }
    }

    /// A string starting at the opening quote: its raw text (escapes as written), the position
    /// after the closing quote.
    fn string(&mut self) -> Result<(usize, usize), Stop> {
        let start = self.i + 1;
        self.i += 1;
        while let Some(c) = self.peek() {
            match c {
                b'\\' => self.i += 2,
                b'"' => {
                    self.i += 1;
                    return Ok((start, self.i - 1));
                }
                _ => self.i += 1,
            }
        }
        Err(None)
    }

    fn object(&mut self, depth: usize) -> Result<(), Stop> {
        self.i += 1;
        let mut keys: HashMap<String, usize> = HashMap::new();
        self.skip_ws();
        if self.peek() == Some(b'}') {
            self.i += 1;
            return Ok(());
        }
        loop {
            self.skip_ws();
            if self.peek() != Some(b'"') {
                return Err(None);
            }
            // The column is counted only for a duplicate: counting it for every key would
            // cost the length of the line each time (a compact file is one line).
            let (line, line_start, at) = (self.line, self.line_start, self.i);
            let (a, b) = self.string()?;
            let raw = &self.text[a..b];
            let key = if raw.contains('\\') {
                serde_json::from_str::<String>(&self.text[a - 1..=b]).map_err(|_| None)?
            } else {
                raw.to_string()
            };
            if let Some(&first_line) = keys.get(&key) {
                return Err(Some(DuplicateKey {
                    key,
                    path: self.path_text(),
                    line,
                    column: 1 + self.text[line_start..at].chars().count(),
                    first_line,
                }));
            }
            keys.insert(key.clone(), line);
            self.skip_ws();
            if self.peek() != Some(b':') {
                return Err(None);
            }
            self.i += 1;
            self.path.push(Step::Key(key));
            self.value(depth + 1)?;
            self.path.pop();
            self.skip_ws();
            match self.peek() {
                Some(b',') => self.i += 1,
                Some(b'}') => {
                    self.i += 1;
                    return Ok(());
                }
                _ => return Err(None),
            }
        }
    }

    fn array(&mut self, depth: usize) -> Result<(), Stop> {
        self.i += 1;
        self.skip_ws();
        if self.peek() == Some(b']') {
            self.i += 1;
            return Ok(());
        }
        let mut index = 0;
        loop {
            self.path.push(Step::Index(index));
            self.value(depth + 1)?;
            self.path.pop();
            self.skip_ws();
            match self.peek() {
                Some(b',') => {
                    self.i += 1;
                    index += 1;
                }
                Some(b']') => {
                    self.i += 1;
                    return Ok(());
                }
                _ => return Err(None),
            }
        }
    }

    fn path_text(&self) -> String {
        let mut s = String::new();
        for step in &self.path {
            match step {
                Step::Key(k) => {
                    if !s.is_empty() {
                        s.push('.');
                    }
                    s.push_str(k);
                }
                Step::Index(i) => s.push_str(&format!("[{i}]")),
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_key_given_twice_is_named_with_its_place() {
        assert_eq!(
            duplicate_key(r#"{"a": 1, "b": [1, {"c": 2}], "d": "x"}"#),
            None
        );
        let d = duplicate_key("{\"budget\": 0.1,\n \"budget\": 0.9}").unwrap();
        assert_eq!((d.key.as_str(), d.path.as_str()), ("budget", ""));
        assert_eq!((d.line, d.column, d.first_line), (2, 2, 1));
        let text = "{\"curves\": [\n {\"points\": []},\n {\"points\": [],\n  \"points\": []}]}";
        let d = duplicate_key(text).unwrap();
        assert_eq!((d.key.as_str(), d.path.as_str()), ("points", "curves[1]"));
        assert_eq!((d.line, d.first_line), (4, 3));
        assert!(
            d.describe()
                .contains("duplicate key \"points\" in curves[1]")
        );
        // The same key in different objects, and keys spelt with escapes.
        assert_eq!(
            duplicate_key(r#"[{"a": 1}, {"a": 2}, {"a": {"a": 3}}]"#),
            None
        );
        let d = duplicate_key(r#"{"m": {"a\u0062": 1, "ab": 2}}"#).unwrap();
        assert_eq!((d.key.as_str(), d.path.as_str()), ("ab", "m"));
        // Strings holding quotes, braces and escapes are skipped whole.
        assert_eq!(duplicate_key(r#"{"a": "\"}{\\", "b": "a"}"#), None);
        // Not JSON: nothing to say (serde_json's to report).
        assert_eq!(duplicate_key("{\"a\" 1, \"a\": 2}"), None);
        assert_eq!(duplicate_key(""), None);
    }
}
