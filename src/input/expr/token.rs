//! The tokenizer of equal- and atom-style formulas.

use super::*;

pub(super) fn tokenize(src: &str) -> Result<Vec<Token>, String> {
    let chars: Vec<(usize, char)> = src.char_indices().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let (b, c) = chars[i];
        let col = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let rest = &src[b..];
        if c.is_ascii_digit() || (c == '.' && rest[1..].starts_with(|d: char| d.is_ascii_digit())) {
            let len = number_len(rest.as_bytes());
            let text = &rest[..len];
            let v: f64 = text
                .parse()
                .map_err(|_| format!("bad number '{text}' (column {col}) in '{src}'"))?;
            out.push(Token {
                tok: Tok::Num(v),
                col,
                text: text.to_string(),
            });
            i += text.chars().count();
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let mut len = rest
                .find(|d: char| !(d.is_ascii_alphanumeric() || d == '_'))
                .unwrap_or(rest.len());
            // c_ID[i], f_ID[i] and the atom references x[ID], vx[ID], mass[ID], …: the index
            // is part of the word.
            if (rest.starts_with("c_")
                || rest.starts_with("f_")
                || AtomValue::from_word(&rest[..len]).is_some())
                && rest[len..].starts_with('[')
            {
                let close = rest[len..].find(']').map(|k| len + k);
                let digits = close.map(|k| &rest[len + 1..k]);
                match (close, digits) {
                    (Some(k), Some(d))
                        if !d.is_empty() && d.bytes().all(|x| x.is_ascii_digit()) =>
                    {
                        len = k + 1
                    }
                    _ => {
                        return Err(format!(
                            "bad index in '{}' (column {col}) in '{src}': expected [N] with N >= 1",
                            &rest[..close.map_or(rest.len(), |k| k + 1)]
                        ));
                    }
                }
            }
            let word = &rest[..len];
            out.push(Token {
                tok: Tok::Word(word.to_string()),
                col,
                text: word.to_string(),
            });
            i += len;
            continue;
        }
        let single = match c {
            '(' => Some(Tok::LParen),
            ')' => Some(Tok::RParen),
            ',' => Some(Tok::Comma),
            _ => None,
        };
        if let Some(tok) = single {
            out.push(Token {
                tok,
                col,
                text: c.to_string(),
            });
            i += 1;
            continue;
        }
        match OPERATORS.iter().find(|op| rest.starts_with(**op)) {
            Some(op) => {
                out.push(Token {
                    tok: Tok::Op(op),
                    col,
                    text: op.to_string(),
                });
                i += op.len();
            }
            None if c == '[' => {
                return Err(format!(
                    "indexed references of variables (v_name[2]) are not supported: '[' (column {col}) \
                     in '{src}'"
                ));
            }
            None => {
                return Err(format!(
                    "unexpected character '{c}' (column {col}) in '{src}'"
                ));
            }
        }
    }
    Ok(out)
}

/// Length in bytes of the number at the start of `s`: digits, an optional fraction and an
/// optional exponent (`e`/`E`, optional sign, at least one digit).
fn number_len(s: &[u8]) -> usize {
    let digits = |mut i: usize| {
        while i < s.len() && s[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut i = digits(0);
    if i < s.len() && s[i] == b'.' {
        i = digits(i + 1);
    }
    if i < s.len() && (s[i] == b'e' || s[i] == b'E') {
        let mut j = i + 1;
        if j < s.len() && (s[j] == b'+' || s[j] == b'-') {
            j += 1;
        }
        let k = digits(j);
        if k > j {
            i = k;
        }
    }
    i
}
