//! The mutations: syntax (delete, duplicate or swap lines, truncate, flip or insert bytes,
//! unbalance brackets) and values (a number replaced by NaN, ±inf, ±1e308, 0, −0.0, its
//! negation, 1e-308 or a huge count; a name swapped for another or an unknown one; a
//! boolean flipped; an enum variant changed). A mutant stacks one to three of them on one
//! scene of the corpus, all drawn from [`Rng::for_mutant`]`(seed, index)`.

use crate::corpus::SeedScene;
use crate::lexer::{Token, TokenKind, tokens};
use crate::rng::Rng;

/// The numbers a real literal is replaced with (`None`: its negation).
pub(crate) const SPECIAL_REALS: &[Option<&str>] = &[
    Some("NaN"),
    Some("inf"),
    Some("-inf"),
    Some("1e308"),
    Some("-1e308"),
    Some("0.0"),
    Some("-0.0"),
    None,
    Some("1e-308"),
    Some("1e6"),
    Some("1e17"),
    Some("-1e-3"),
];

/// The numbers an integer literal (a count, a node, an index) is replaced with.
pub(crate) const SPECIAL_COUNTS: &[Option<&str>] = &[
    Some("0"),
    Some("1"),
    Some("18446744073709551615"),
    Some("4294967296"),
    Some("1000000"),
    Some("100000"),
    Some("20000"),
    None,
];

/// Names a name is replaced with, besides the other names of the scene.
const ODD_NAMES: &[&str] = &["\"unknown\"", "\"\"", "\"ground\""];

/// Variants an enum variant is replaced with, besides the other variants of the scene.
const EXTRA_VARIANTS: &[&str] = &["Absolute", "Relative", "Spatial", "Planar", "None", "Fixed"];

/// Bytes that an inserted or replaced byte is drawn from: RON's punctuation, digits and a
/// few letters, so that most byte mutations stay near the grammar.
const BYTES: &[u8] = b"()[]{},:\"-+.0123456789eE_ aZ/*\n";

/// A mutated scene and how it was made.
#[derive(Clone, Debug)]
pub struct Mutant {
    /// The seed scene it was made from.
    pub seed_scene: String,
    /// The mutated text.
    pub text: String,
    /// One line per mutation applied, in order.
    pub mutations: Vec<String>,
}

/// The mutant `index` of the campaign `seed` over `corpus`.
pub fn mutant(corpus: &[SeedScene], seed: u64, index: u64) -> Mutant {
    let mut rng = Rng::for_mutant(seed, index);
    let scene = rng.pick(corpus);
    let mut text = scene.text.clone();
    let count = *rng.pick(&[1, 1, 1, 2, 2, 3]);
    let mut mutations = Vec::with_capacity(count);
    for _ in 0..count {
        let (next, what) = if rng.chance(3, 4) {
            value_mutation(&text, &mut rng)
        } else {
            syntax_mutation(&text, &mut rng)
        };
        text = next;
        mutations.push(what);
    }
    Mutant {
        seed_scene: scene.path.display().to_string(),
        text,
        mutations,
    }
}

/// Replace one literal by a hostile value of the same kind (or a syntax mutation when
/// the text has no literal left).
fn value_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let all = tokens(text);
    // Numbers first: most of what validation must check is a number.
    let kind = *rng.pick(&[
        TokenKind::Number,
        TokenKind::Number,
        TokenKind::Number,
        TokenKind::Number,
        TokenKind::Name,
        TokenKind::Boolean,
        TokenKind::Variant,
    ]);
    let of_kind: Vec<Token> = all.iter().copied().filter(|t| t.kind == kind).collect();
    let candidates = if of_kind.is_empty() {
        all.clone()
    } else {
        of_kind
    };
    if candidates.is_empty() {
        return syntax_mutation(text, rng);
    }
    let token = *rng.pick(&candidates);
    let old = &text[token.start..token.end];
    let new = match token.kind {
        TokenKind::Number => {
            let integer = old
                .trim_start_matches('-')
                .bytes()
                .all(|c| c.is_ascii_digit());
            // Mostly a hostile value of the literal's own kind, sometimes the other kind.
            let specials = if integer == rng.chance(7, 8) {
                SPECIAL_COUNTS
            } else {
                SPECIAL_REALS
            };
            match rng.pick(specials) {
                Some(s) => s.to_string(),
                None => negate(old),
            }
        }
        TokenKind::Boolean => if old == "true" { "false" } else { "true" }.to_string(),
        TokenKind::Name => other_literal(text, &all, TokenKind::Name, ODD_NAMES, rng),
        TokenKind::Variant => other_literal(text, &all, TokenKind::Variant, EXTRA_VARIANTS, rng),
    };
    let what = format!("line {}: `{old}` -> `{new}`", line_of(text, token.start));
    (splice(text, token.start, token.end, &new), what)
}

/// Another literal of `kind` from the text, or one of `extra`.
fn other_literal(
    text: &str,
    all: &[Token],
    kind: TokenKind,
    extra: &[&str],
    rng: &mut Rng,
) -> String {
    let same: Vec<&Token> = all.iter().filter(|t| t.kind == kind).collect();
    if rng.chance(1, 3) {
        rng.pick(extra).to_string()
    } else {
        let t = rng.pick(&same);
        text[t.start..t.end].to_string()
    }
}

/// `-x` for `x`, `x` for `-x`.
pub(crate) fn negate(number: &str) -> String {
    match number.strip_prefix('-') {
        Some(positive) => positive.to_string(),
        None => format!("-{number}"),
    }
}

/// One syntax mutation of `text`.
fn syntax_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    match rng.below(7) {
        0 | 1 if !lines.is_empty() => line_deleted_or_duplicated(&lines, rng),
        2 if lines.len() > 1 => lines_swapped(&lines, rng),
        3 => truncation(text, rng),
        4 => unbalance(text, rng),
        _ => byte_mutation(text, rng, BYTES),
    }
}

/// A line (of `lines`, non-empty, each with its newline) deleted or duplicated.
pub(crate) fn line_deleted_or_duplicated(lines: &[&str], rng: &mut Rng) -> (String, String) {
    let i = rng.below(lines.len());
    let mut out = lines.to_vec();
    let what = if rng.chance(1, 2) {
        out.remove(i);
        format!("line {}: deleted", i + 1)
    } else {
        out.insert(i, lines[i]);
        format!("line {}: duplicated", i + 1)
    };
    (out.concat(), what)
}

/// Two lines of `lines` (each with its newline) swapped.
pub(crate) fn lines_swapped(lines: &[&str], rng: &mut Rng) -> (String, String) {
    let (i, j) = (rng.below(lines.len()), rng.below(lines.len()));
    let mut out = lines.to_vec();
    out.swap(i, j);
    (
        out.concat(),
        format!("lines {} and {}: swapped", i + 1, j + 1),
    )
}

/// The text cut at a random char boundary.
pub(crate) fn truncation(text: &str, rng: &mut Rng) -> (String, String) {
    let at = boundary(text, rng.below(text.len() + 1));
    (
        text[..at].to_string(),
        format!("truncated at byte {at} (line {})", line_of(text, at)),
    )
}

/// Delete a bracket or insert a stray one.
fn unbalance(text: &str, rng: &mut Rng) -> (String, String) {
    let brackets: Vec<usize> = text
        .bytes()
        .enumerate()
        .filter(|(_, c)| b"()[]".contains(c))
        .map(|(i, _)| i)
        .collect();
    if brackets.is_empty() || rng.chance(1, 2) {
        let at = boundary(text, rng.below(text.len() + 1));
        let c = *rng.pick(&["(", ")", "[", "]"]);
        let what = format!("line {}: inserted `{c}`", line_of(text, at));
        (splice(text, at, at, c), what)
    } else {
        let at = *rng.pick(&brackets);
        let what = format!(
            "line {}: deleted `{}`",
            line_of(text, at),
            &text[at..at + 1]
        );
        (splice(text, at, at + 1, ""), what)
    }
}

/// Flip a bit of, replace, or insert before a byte, the new bytes drawn from `alphabet`
/// (ASCII, and a flip keeps an ASCII byte ASCII, so the text stays UTF-8).
pub(crate) fn byte_mutation(text: &str, rng: &mut Rng, alphabet: &[u8]) -> (String, String) {
    let at = boundary(text, rng.below(text.len() + 1));
    let line = line_of(text, at);
    let next = text[at..].chars().next();
    let byte = *rng.pick(alphabet) as char;
    match (rng.below(3), next) {
        (0, Some(c)) if c.is_ascii() => {
            let flipped = ((c as u8) ^ (1 << rng.below(7))) as char;
            (
                splice(text, at, at + 1, &flipped.to_string()),
                format!(
                    "line {line}: `{}` flipped to {:?}",
                    c.escape_debug(),
                    flipped
                ),
            )
        }
        (1, Some(c)) => (
            splice(text, at, at + c.len_utf8(), &byte.to_string()),
            format!("line {line}: `{}` replaced by {byte:?}", c.escape_debug()),
        ),
        _ => (
            splice(text, at, at, &byte.to_string()),
            format!("line {line}: inserted {byte:?}"),
        ),
    }
}

/// `text` with `start..end` replaced by `with`.
pub(crate) fn splice(text: &str, start: usize, end: usize, with: &str) -> String {
    let mut out = String::with_capacity(text.len() + with.len());
    out.push_str(&text[..start]);
    out.push_str(with);
    out.push_str(&text[end..]);
    out
}

/// The nearest char boundary at or before `at`.
pub(crate) fn boundary(text: &str, mut at: usize) -> usize {
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// The 1-based line of byte `at`.
pub(crate) fn line_of(text: &str, at: usize) -> usize {
    text[..at].bytes().filter(|&c| c == b'\n').count() + 1
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn corpus() -> Vec<SeedScene> {
        let text =
            "(name: \"a\", dim: Planar, flexible: true, bodies: [(name: \"b\", mass: 2.5)],\n \
                    n: 10, g: [0.0, -9.81])\n"
                .to_string();
        vec![SeedScene {
            path: PathBuf::from("s.ron"),
            text,
        }]
    }

    #[test]
    fn the_same_seed_and_index_give_the_same_mutant() {
        let c = corpus();
        for index in 0..200 {
            let (a, b) = (mutant(&c, 5, index), mutant(&c, 5, index));
            assert_eq!((a.text, a.mutations), (b.text, b.mutations));
        }
    }

    #[test]
    fn every_mutant_differs_from_its_seed_or_says_why_not() {
        let c = corpus();
        let changed = (0..500)
            .filter(|&i| mutant(&c, 9, i).text != c[0].text)
            .count();
        // A swap of a line with itself or a name swapped for itself can leave the text
        // unchanged; nearly all mutants must differ.
        assert!(
            changed > 450,
            "only {changed} of 500 mutants differ from the seed"
        );
    }

    #[test]
    fn value_mutations_reach_every_hostile_number() {
        let c = corpus();
        let texts: Vec<String> = (0..3000).map(|i| mutant(&c, 1, i).text).collect();
        for special in [
            "NaN",
            "-inf",
            "1e308",
            "-0.0",
            "18446744073709551615",
            "1e-308",
            "100000",
        ] {
            assert!(
                texts.iter().any(|t| t.contains(special)),
                "{special} never drawn"
            );
        }
        assert!(
            texts.iter().any(|t| t.contains("flexible: false")),
            "no boolean flipped"
        );
        assert!(
            texts.iter().any(|t| t.contains("\"unknown\"")),
            "no unknown name"
        );
    }

    #[test]
    fn mutations_of_multibyte_text_cut_only_at_char_boundaries() {
        // A cut inside `ρ` or `³` would panic in the slicing.
        let text = "// ρ = 7850 kg/m³ –\n(a: \"é\")\n".to_string();
        let c = vec![SeedScene {
            path: PathBuf::from("u.ron"),
            text,
        }];
        for i in 0..2000 {
            assert!(!mutant(&c, 3, i).mutations.is_empty());
        }
    }
}
