//! The library speaks to every front end alike: no message spells a command-line flag (options
//! are named by `words::Opt` and spelled by each front end's `Wording`), and no public function
//! returns a bare `Result<_, String>` (errors are typed). The run folder's layout is spelled
//! once: no file name under `states/`, `modes/` or `iterations/` outside `run_layout`. One
//! cancellation type: no public function or trait method takes or gives a bare `AtomicBool`
//! (a search stops on a `cancel::Cancel`).
//!
//! All of them read the library's sources: a small Rust lexer finds string literals and `pub fn`
//! signatures outside comments (doc comments included) and outside `#[cfg(test)]` items.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// A token of Rust source, with the line it starts on.
#[derive(Debug, Clone, PartialEq)]
enum Tok {
    /// An identifier, keyword or number.
    Word(String),
    /// A string literal's source text (between its quotes, escapes as written).
    Str(String),
    /// Any other character.
    Punct(char),
}

/// The tokens of `src`, each with its line (1-based); comments dropped.
fn lex(src: &str) -> Vec<(Tok, usize)> {
    let c: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    while i < c.len() {
        let ch = c[i];
        let next = c.get(i + 1).copied();
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && next == Some('/') {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && next == Some('*') {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if c[i] == '\n' {
                        line += 1;
                    }
                    i += 1;
                }
            }
        } else if ch == '"' || raw_string_start(&c, i).is_some() {
            let start = line;
            let (text, end) = match raw_string_start(&c, i) {
                Some((hashes, open)) => {
                    let close: Vec<char> = std::iter::once('"')
                        .chain(std::iter::repeat_n('#', hashes))
                        .collect();
                    let mut j = open;
                    while j < c.len() && c[j..].iter().take(close.len()).ne(close.iter()) {
                        j += 1;
                    }
                    (c[open..j].iter().collect::<String>(), j + close.len())
                }
                None => {
                    let mut j = i + 1;
                    while j < c.len() && c[j] != '"' {
                        j += if c[j] == '\\' { 2 } else { 1 };
                    }
                    (c[i + 1..j.min(c.len())].iter().collect(), j + 1)
                }
            };
            line += text.matches('\n').count();
            out.push((Tok::Str(text), start));
            i = end;
        } else if ch == '\'' {
            // A character literal ('x', '\n', '\u{..}', '"') or a lifetime ('a).
            if next == Some('\\') {
                let mut j = i + 3;
                while j < c.len() && c[j] != '\'' {
                    j += 1;
                }
                i = j + 1;
            } else if c.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                out.push((Tok::Punct('\''), line));
                i += 1;
            }
        } else if ident(ch) {
            let mut j = i;
            while j < c.len() && ident(c[j]) {
                j += 1;
            }
            out.push((Tok::Word(c[i..j].iter().collect()), line));
            i = j;
        } else {
            out.push((Tok::Punct(ch), line));
            i += 1;
        }
    }
    out
}

/// At a raw or prefixed string literal (`r"…"`, `r#"…"#`, `b"…"`, `br#"…"#`, `c"…"`):
/// for a raw one its number of `#`s and where its text starts; `None` elsewhere (a plain
/// `b"…"` is treated as raw with no escapes to skip, which is close enough here).
fn raw_string_start(c: &[char], i: usize) -> Option<(usize, usize)> {
    if i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_') {
        return None;
    }
    let mut j = i;
    if matches!(c.get(j), Some('b' | 'c')) {
        j += 1;
    }
    let raw = c.get(j) == Some(&'r');
    if raw {
        j += 1;
    }
    if j == i {
        return None;
    }
    let mut hashes = 0;
    while raw && c.get(j) == Some(&'#') {
        hashes += 1;
        j += 1;
    }
    (c.get(j) == Some(&'"')).then_some((hashes, j + 1))
}

/// The tokens of `src` outside `#[cfg(test)]` items, and the files of `#[cfg(test)] mod x;`
/// declarations (beside `path`).
fn outside_tests(path: &Path, toks: &[(Tok, usize)]) -> (Vec<(Tok, usize)>, Vec<PathBuf>) {
    let mut kept = Vec::new();
    let mut test_files = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        if let Some((inner, end)) = cfg_test_attribute(toks, i) {
            if inner {
                return (kept, test_files); // #![cfg(test)]: the whole file
            }
            i = end;
            // Further attributes of the same item.
            while toks.get(i).map(|t| &t.0) == Some(&Tok::Punct('#')) {
                i = matching(toks, i + 1) + 1;
            }
            // The item: up to its `;` or through its `{ … }` block.
            let mut depth = 0i32;
            let mut words = Vec::new();
            while i < toks.len() {
                match &toks[i].0 {
                    Tok::Punct('(' | '[') => depth += 1,
                    Tok::Punct(')' | ']') => depth -= 1,
                    Tok::Punct(';') if depth == 0 => break,
                    Tok::Punct('{') if depth == 0 => {
                        i = matching(toks, i);
                        words.clear();
                        break;
                    }
                    Tok::Word(w) => words.push(w.clone()),
                    _ => {}
                }
                i += 1;
            }
            if let [.., m, name] = words.as_slice()
                && m == "mod"
            {
                test_files.extend(module_files(path, name));
            }
            i += 1;
        } else {
            kept.push(toks[i].clone());
            i += 1;
        }
    }
    (kept, test_files)
}

/// At `#[cfg(…test…)]` (not `not(test)`) or `#![cfg(test)]` starting at `i`: whether it is an
/// inner attribute and the index after it.
fn cfg_test_attribute(toks: &[(Tok, usize)], i: usize) -> Option<(bool, usize)> {
    if toks[i].0 != Tok::Punct('#') {
        return None;
    }
    let inner = toks.get(i + 1).map(|t| &t.0) == Some(&Tok::Punct('!'));
    let open = if inner { i + 2 } else { i + 1 };
    if toks.get(open).map(|t| &t.0) != Some(&Tok::Punct('['))
        || toks.get(open + 1).map(|t| &t.0) != Some(&Tok::Word("cfg".into()))
    {
        return None;
    }
    let close = matching(toks, open);
    let words: Vec<&str> = toks[open..close]
        .iter()
        .filter_map(|t| match &t.0 {
            Tok::Word(w) => Some(w.as_str()),
            _ => None,
        })
        .collect();
    (words.contains(&"test") && !words.contains(&"not")).then_some((inner, close + 1))
}

/// The index of the bracket closing the one at `i`.
fn matching(toks: &[(Tok, usize)], i: usize) -> usize {
    let mut depth = 0i32;
    for (j, (t, _)) in toks.iter().enumerate().skip(i) {
        match t {
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(')' | ']' | '}') => {
                depth -= 1;
                if depth == 0 {
                    return j;
                }
            }
            _ => {}
        }
    }
    toks.len()
}

/// The files a `mod name;` in `path` may live in.
fn module_files(path: &Path, name: &str) -> Vec<PathBuf> {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    let dir = path.parent().expect("a file's folder");
    let dir = if matches!(stem, "mod" | "lib" | "main") {
        dir.to_path_buf()
    } else {
        dir.join(stem)
    };
    vec![
        dir.join(format!("{name}.rs")),
        dir.join(name).join("mod.rs"),
    ]
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("a readable folder")
        .map(|e| e.expect("a folder entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The library's sources, each with its tokens outside comments and test items.
fn library_tokens() -> Vec<(String, Vec<(Tok, usize)>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    let mut test_files = HashSet::new();
    let mut lexed = Vec::new();
    for f in &files {
        let src = std::fs::read_to_string(f).expect("a readable source file");
        let (toks, tests) = outside_tests(f, &lex(&src));
        test_files.extend(tests);
        lexed.push((f.clone(), toks));
    }
    lexed
        .into_iter()
        .filter(|(f, _)| !test_files.contains(f))
        .map(|(f, toks)| {
            let name = f.strip_prefix(root).unwrap_or(&f).display().to_string();
            (name, toks)
        })
        .collect()
}

/// Where a string literal's text spells a command-line flag (`--` then a letter): its lines.
fn flag_lines(text: &str, start: usize) -> Vec<(usize, String)> {
    let b = text.as_bytes();
    let mut found = Vec::new();
    for i in 0..b.len().saturating_sub(2) {
        let before_ok = i == 0 || !(b[i - 1] == b'-' || b[i - 1].is_ascii_alphanumeric());
        if before_ok && b[i] == b'-' && b[i + 1] == b'-' && b[i + 2].is_ascii_alphabetic() {
            let line = start + text[..i].matches('\n').count();
            let word: String = text[i..]
                .chars()
                .take_while(|c| *c == '-' || c.is_ascii_alphanumeric())
                .collect();
            found.push((line, word));
        }
    }
    found
}

#[test]
fn no_library_message_spells_a_command_line_flag() {
    let mut found = Vec::new();
    for (file, toks) in library_tokens() {
        for (t, line) in &toks {
            if let Tok::Str(text) = t {
                for (l, flag) in flag_lines(text, *line) {
                    found.push(format!("{file}:{l}: {flag}"));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "{} string literal(s) of the library spell a command-line flag; name the option \
         with words::Opt in a words::Message instead:\n{}",
        found.len(),
        found.join("\n")
    );
}

/// The return type of a `pub fn` whose tokens start at `i` (after `pub fn`), spaces dropped.
fn return_type(toks: &[(Tok, usize)], i: usize) -> String {
    let mut depth = 0i32;
    let mut j = i;
    let mut ret = None;
    while j < toks.len() {
        match &toks[j].0 {
            Tok::Punct('(' | '[') => depth += 1,
            Tok::Punct(')' | ']') => depth -= 1,
            Tok::Punct('{' | ';') if depth == 0 => break,
            Tok::Word(w) if depth == 0 && w == "where" => break,
            Tok::Punct('-')
                if depth == 0
                    && ret.is_none()
                    && toks.get(j + 1).map(|t| &t.0) == Some(&Tok::Punct('>')) =>
            {
                ret = Some(String::new());
                j += 2;
                continue;
            }
            _ => {}
        }
        if let Some(r) = ret.as_mut() {
            match &toks[j].0 {
                Tok::Word(w) => {
                    if r.ends_with(|c: char| c.is_alphanumeric() || c == '_') {
                        r.push(' ');
                    }
                    r.push_str(w);
                }
                Tok::Punct(p) => r.push(*p),
                Tok::Str(s) => r.push_str(s),
            }
        }
        j += 1;
    }
    ret.unwrap_or_default()
}

/// Whether a return type holds a `Result<_, String>`.
fn returns_string_error(ty: &str) -> bool {
    let ty = ty.replace("->", "→");
    let mut rest = ty.as_str();
    while let Some(at) = rest.find("Result<") {
        let before = rest[..at].chars().next_back();
        let args = &rest[at + "Result<".len()..];
        rest = args;
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue; // FooResult<…>
        }
        let (mut depth, mut parts, mut cur) = (0, Vec::new(), String::new());
        for ch in args.chars() {
            match ch {
                '<' | '(' | '[' => depth += 1,
                '>' | ')' | ']' if depth == 0 => break,
                '>' | ')' | ']' => depth -= 1,
                ',' if depth == 0 => {
                    parts.push(std::mem::take(&mut cur));
                    continue;
                }
                _ => {}
            }
            cur.push(ch);
        }
        parts.push(cur);
        if parts
            .get(1)
            .is_some_and(|e| matches!(e.trim(), "String" | "std::string::String"))
        {
            return true;
        }
    }
    false
}

/// Whether a token qualifies a `fn` (`pub const fn`, `pub async fn`, `pub unsafe fn`).
fn qualifies_fn(t: Option<&(Tok, usize)>) -> bool {
    match t {
        Some((Tok::Word(w), _)) => ["const", "async", "unsafe"].contains(&w.as_str()),
        _ => false,
    }
}

#[test]
fn no_public_function_returns_a_string_error() {
    let mut found = Vec::new();
    for (file, toks) in library_tokens() {
        for (i, (t, line)) in toks.iter().enumerate() {
            if *t != Tok::Word("pub".into()) {
                continue;
            }
            // `pub fn`, `pub const fn`, `pub async fn`, `pub unsafe fn`.
            let mut j = i + 1;
            while qualifies_fn(toks.get(j)) {
                j += 1;
            }
            if toks.get(j).map(|t| &t.0) != Some(&Tok::Word("fn".into())) {
                continue;
            }
            let ty = return_type(&toks, j + 1);
            if returns_string_error(&ty) {
                let name = match toks.get(j + 1).map(|t| &t.0) {
                    Some(Tok::Word(w)) => w.clone(),
                    _ => String::new(),
                };
                found.push(format!("{file}:{line}: {name} -> {ty}"));
            }
        }
    }
    assert!(
        found.is_empty(),
        "{} public function(s) of the library return Result<_, String>; give each a typed \
         error:\n{}",
        found.len(),
        found.join("\n")
    );
}

/// The words of the signature of the `fn` whose name is at `i` (up to its body or `;`).
fn signature_words(toks: &[(Tok, usize)], i: usize) -> Vec<&str> {
    let mut depth = 0i32;
    let mut words = Vec::new();
    for (t, _) in &toks[i..] {
        match t {
            Tok::Punct('(' | '[' | '<') => depth += 1,
            Tok::Punct(')' | ']') => depth -= 1,
            Tok::Punct('>') if depth > 0 => depth -= 1,
            Tok::Punct('{' | ';') if depth <= 0 => break,
            Tok::Word(w) => words.push(w.as_str()),
            _ => {}
        }
    }
    words
}

#[test]
fn cancellation_goes_by_one_token_type() {
    let mut found = Vec::new();
    for (file, toks) in library_tokens() {
        // The token ranges of trait bodies: their methods are a caller's interface too.
        let mut in_trait = vec![false; toks.len()];
        for (i, (t, _)) in toks.iter().enumerate() {
            if *t == Tok::Word("trait".into())
                && let Some(open) = toks[i..]
                    .iter()
                    .position(|(t, _)| *t == Tok::Punct('{'))
                    .map(|p| i + p)
            {
                let close = matching(&toks, open);
                in_trait[open..close.min(toks.len())].fill(true);
            }
        }
        for (i, (t, line)) in toks.iter().enumerate() {
            if *t != Tok::Word("fn".into()) {
                continue;
            }
            let public = (1..=3).any(|k| {
                i.checked_sub(k)
                    .is_some_and(|j| toks[j].0 == Tok::Word("pub".into()))
            });
            if (public || in_trait[i]) && signature_words(&toks, i).contains(&"AtomicBool") {
                found.push(format!("{file}:{line}"));
            }
        }
    }
    assert!(
        found.is_empty(),
        "public functions or trait methods taking a bare AtomicBool (take a cancel::Cancel):\n{}",
        found.join("\n")
    );
    let toks = lex("pub trait H { fn stop(&self, flag: &AtomicBool) -> bool; }");
    assert_eq!(
        signature_words(&toks, 4),
        ["fn", "stop", "self", "flag", "AtomicBool", "bool"]
    );
}

/// Whether a string literal's text spells a path of the run folder's own folders (`states/…`,
/// `modes/…`, `iterations/…`, or `states` or `modes` alone; a bare `iterations` is also the
/// record's field).
fn spells_run_layout(text: &str) -> bool {
    ["states", "modes", "iterations"].iter().any(|dir| {
        (text == *dir && *dir != "iterations")
            || text.match_indices(&format!("{dir}/")).any(|(i, _)| {
                !text[..i]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_')
            })
    })
}

#[test]
fn the_run_folders_layout_is_spelled_in_run_layout_alone() {
    let mut found = Vec::new();
    for (file, toks) in library_tokens() {
        if file.ends_with("run_layout.rs") {
            continue;
        }
        for (t, line) in &toks {
            if let Tok::Str(text) = t
                && spells_run_layout(text)
            {
                found.push(format!("{file}:{line}: \"{text}\""));
            }
        }
    }
    assert!(
        found.is_empty(),
        "{} string literal(s) spell the run folder's layout outside run_layout; name the file \
         with run_layout's functions instead:\n{}",
        found.len(),
        found.join("\n")
    );
    // The check itself.
    assert!(spells_run_layout("states/{k:04}.bin") && spells_run_layout("modes"));
    assert!(spells_run_layout("x/iterations/0001.obj") && !spells_run_layout("iterations"));
    assert!(!spells_run_layout("eigenmodes/x") && !spells_run_layout("modes: 2 zero"));
}

#[test]
fn the_checks_see_what_they_look_for() {
    let src = r##"
        /// "--doc" in a doc comment is fine
        fn f() -> Result<(), String> { let _ = ("--one", '"', '\'', 'a', r#"--two"#); }
        pub fn g(x: Vec<Result<u8, String>>) -> Result<HashMap<String, String>, E> { }
        pub fn h() -> Result<Vec<u8>, String> where T: Fn() -> u8 { "a\
            --three --- -->" }
        #[cfg(test)]
        mod tests { const X: &str = "--hidden"; }
        #[cfg(not(test))]
        const Y: &str = "--four";
    "##;
    let toks = lex(src);
    let (toks, _) = outside_tests(Path::new("src/lib.rs"), &toks);
    let flags: Vec<(usize, String)> = toks
        .iter()
        .filter_map(|(t, l)| match t {
            Tok::Str(s) => Some(flag_lines(s, *l)),
            _ => None,
        })
        .flatten()
        .collect();
    let words = |v: &[(usize, String)]| {
        v.iter()
            .map(|(l, w)| format!("{l}:{w}"))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        words(&flags),
        ["3:--one", "3:--two", "6:--three", "10:--four"]
    );
    let fns: Vec<String> = toks
        .iter()
        .enumerate()
        .filter(|(_, (t, _))| *t == Tok::Word("fn".into()))
        .map(|(i, _)| return_type(&toks, i + 1))
        .collect();
    assert_eq!(
        fns,
        [
            "Result<(),String>",
            "Result<HashMap<String,String>,E>",
            "Result<Vec<u8>,String>"
        ]
    );
    let judged: Vec<bool> = fns.iter().map(|t| returns_string_error(t)).collect();
    assert_eq!(judged, [true, false, true]);
}
