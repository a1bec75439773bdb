//! Turning LAMMPS input text into commands: continuation lines, comments, quoting.
//! Variable substitution happens in the interpreter, between [`strip_comment`] and [`split_words`].

/// One logical input line: the text after joining `&` continuations, and its first line number.
#[derive(Clone, Debug, PartialEq)]
pub struct RawLine {
    /// 1-based line number of the first physical line.
    pub line: usize,
    /// The joined text.
    pub text: String,
}

/// Join lines ending in `&` (LAMMPS continuation) and number them.
pub fn logical_lines(text: &str) -> Vec<RawLine> {
    let mut out = Vec::new();
    let mut cur: Option<RawLine> = None;
    for (k, line) in text.lines().enumerate() {
        let trimmed = line.trim_end();
        let (body, cont) = match trimmed.strip_suffix('&') {
            Some(b) => (b, true),
            None => (trimmed, false),
        };
        let entry = cur.get_or_insert_with(|| RawLine {
            line: k + 1,
            text: String::new(),
        });
        if !entry.text.is_empty() {
            entry.text.push(' ');
        }
        entry.text.push_str(body);
        if !cont && let Some(done) = cur.take() {
            out.push(done);
        }
    }
    if let Some(done) = cur.take() {
        out.push(done);
    }
    out
}

/// Remove a `#` comment that is outside quotes.
///
/// Scans bytes, not characters: every delimiter is ASCII, so it never matches inside a
/// multi-byte character, and the cut before `#` is a character boundary (a `&s[i..]` here
/// panicked on the first non-ASCII character, found by the fuzzer: tests/fuzz_regressions.rs).
pub fn strip_comment(s: &str) -> &str {
    let mut quote: Option<&[u8]> = None;
    let b = s.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let rest = &b[i..];
        match quote {
            None => {
                if rest.starts_with(b"\"\"\"") {
                    quote = Some(b"\"\"\"");
                    i += 3;
                    continue;
                }
                match b[i] {
                    b'#' => return &s[..i],
                    b'"' => quote = Some(b"\""),
                    b'\'' => quote = Some(b"'"),
                    _ => {}
                }
            }
            Some(q) => {
                if rest.starts_with(q) {
                    i += q.len();
                    quote = None;
                    continue;
                }
            }
        }
        i += 1;
    }
    s
}

/// Split into words on whitespace; a word in single, double or triple double quotes keeps its
/// spaces and loses the quotes. Errors on an unterminated quote.
pub fn split_words(s: &str) -> Result<Vec<String>, String> {
    let mut words = Vec::new();
    let mut rest = s.trim_start();
    while !rest.is_empty() {
        let (q, skip) = if rest.starts_with("\"\"\"") {
            (Some("\"\"\""), 3)
        } else if rest.starts_with('"') {
            (Some("\""), 1)
        } else if rest.starts_with('\'') {
            (Some("'"), 1)
        } else {
            (None, 0)
        };
        match q {
            Some(q) => {
                let body = &rest[skip..];
                let end = body
                    .find(q)
                    .ok_or_else(|| format!("unterminated quote {q} in: {s}"))?;
                words.push(body[..end].to_string());
                rest = body[end + q.len()..].trim_start();
            }
            None => {
                let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
                words.push(rest[..end].to_string());
                rest = rest[end..].trim_start();
            }
        }
    }
    Ok(words)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuation_and_numbering() {
        let l = logical_lines("a &\n  b\nc\n");
        assert_eq!(
            l[0],
            RawLine {
                line: 1,
                text: "a    b".into()
            }
        );
        assert_eq!(l[1].line, 3);
    }

    #[test]
    fn comments_and_quotes() {
        assert_eq!(strip_comment("run 10 # go"), "run 10 ");
        assert_eq!(strip_comment("print \"a # b\" # c"), "print \"a # b\" ");
        assert_eq!(
            split_words("print \"a b\" 'c d' e").unwrap(),
            vec!["print", "a b", "c d", "e"]
        );
        assert!(split_words("print \"abc").is_err());
    }
}
