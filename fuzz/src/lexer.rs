//! Just enough of a RON lexer to find the literals a value mutation replaces: numbers,
//! quoted names, booleans and enum variants, outside comments.

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TokenKind {
    /// A numeric literal (`-1.5e3`, `20`).
    Number,
    /// A quoted string (a name: body, marker, joint, sensor).
    Name,
    /// `true` or `false`.
    Boolean,
    /// An identifier starting with a capital letter that is not a field name: an enum
    /// variant (`Planar`, `Revolute`, `Some`).
    Variant,
}

/// A token: its kind and its byte range in the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Token {
    /// What it is.
    pub kind: TokenKind,
    /// First byte.
    pub start: usize,
    /// One past the last byte.
    pub end: usize,
}

/// The value tokens of `text`, in order (comments skipped).
pub fn tokens(text: &str) -> Vec<Token> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'/' && b.get(i + 1) == Some(&b'/') {
            i = skip_until(b, i, b"\n");
        } else if c == b'/' && b.get(i + 1) == Some(&b'*') {
            i = skip_until(b, i + 2, b"*/") + 2;
        } else if c == b'"' {
            let end = string_end(b, i + 1);
            out.push(Token {
                kind: TokenKind::Name,
                start: i,
                end,
            });
            i = end;
        } else if c.is_ascii_digit() || (c == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let end = number_end(b, i + 1);
            out.push(Token {
                kind: TokenKind::Number,
                start: i,
                end,
            });
            i = end;
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let end = ident_end(b, i);
            if let Some(kind) = word_kind(&text[i..end], b, end) {
                out.push(Token {
                    kind,
                    start: i,
                    end,
                });
            }
            i = end;
        } else {
            i += 1;
        }
    }
    out
}

/// The index of the first occurrence of `pattern` at or after `from` (or the end).
fn skip_until(b: &[u8], from: usize, pattern: &[u8]) -> usize {
    (from..b.len())
        .find(|&j| b[j..].starts_with(pattern))
        .unwrap_or(b.len())
        .min(b.len())
}

/// One past the closing quote of a string whose body starts at `from`.
fn string_end(b: &[u8], from: usize) -> usize {
    let mut j = from;
    while j < b.len() {
        match b[j] {
            b'\\' => j += 2,
            b'"' => return j + 1,
            _ => j += 1,
        }
    }
    b.len()
}

/// One past the last byte of a number whose first digit precedes `from`.
fn number_end(b: &[u8], from: usize) -> usize {
    let mut j = from;
    while j < b.len() {
        let c = b[j];
        let exponent_sign = (c == b'-' || c == b'+') && matches!(b[j - 1], b'e' | b'E');
        if c.is_ascii_digit() || c == b'.' || c == b'e' || c == b'E' || c == b'_' || exponent_sign {
            j += 1;
        } else {
            break;
        }
    }
    j
}

/// One past the last byte of an identifier starting at `from`.
fn ident_end(b: &[u8], from: usize) -> usize {
    let mut j = from;
    while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
        j += 1;
    }
    j
}

/// The kind of a word ending at `end`: a boolean, a variant (capitalised, not followed by
/// `:`), or nothing (a field name or another word).
fn word_kind(word: &str, b: &[u8], end: usize) -> Option<TokenKind> {
    let next = b[end..].iter().find(|c| !c.is_ascii_whitespace());
    if next == Some(&b':') {
        return None;
    }
    match word {
        "true" | "false" => Some(TokenKind::Boolean),
        w if w.starts_with(|c: char| c.is_ascii_uppercase()) => Some(TokenKind::Variant),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds_and_texts(text: &str) -> Vec<(TokenKind, &str)> {
        tokens(text)
            .into_iter()
            .map(|t| (t.kind, &text[t.start..t.end]))
            .collect()
    }

    #[test]
    fn finds_numbers_names_booleans_and_variants_outside_comments() {
        let text = "// step: 1e-3 \"no\"\n(name: \"rod\", dim: Planar, g: [0.0, -9.81], \
                    flexible: false, e: 2.1e11, s: Some(3), /* 5 */ n: 10)";
        assert_eq!(
            kinds_and_texts(text),
            vec![
                (TokenKind::Name, "\"rod\""),
                (TokenKind::Variant, "Planar"),
                (TokenKind::Number, "0.0"),
                (TokenKind::Number, "-9.81"),
                (TokenKind::Boolean, "false"),
                (TokenKind::Number, "2.1e11"),
                (TokenKind::Variant, "Some"),
                (TokenKind::Number, "3"),
                (TokenKind::Number, "10"),
            ]
        );
    }

    #[test]
    fn negative_exponents_stay_in_the_number() {
        assert_eq!(
            kinds_and_texts("x: 1.5e-3,"),
            vec![(TokenKind::Number, "1.5e-3")]
        );
    }
}
