//! Mutants of the reader inputs: one seed of the corpus with one to three mutations, each
//! on one of its files, all drawn from [`Rng::for_mutant`]`(seed, index)`, and for one in
//! four mutants of a reducible seed a [`Reduction`] of the model read.
//!
//! - *Value mutations* (half): a number of the file replaced, as in the scenes, by a
//!   hostile value of its kind (`NaN`, `inf`, `1e308`, `0`, `18446744073709551615`, …
//!   from [`crate::mutate`]'s lists), its negation, or an integer moved by one.
//! - *Syntax mutations* (a quarter): a line deleted, duplicated or swapped, the text
//!   truncated, a byte flipped, replaced or inserted (FE-file punctuation and digits).
//! - *Format-aware mutations* (a quarter), among those the file admits: a Matrix Market
//!   banner word or the size line changed; an Abaqus keyword line's keyword or
//!   parameters altered; a DOF label changed; line endings made CRLF or CR, a byte-order
//!   mark or tabs added.

use super::corpus::{ReaderSeed, describe};
use super::{ReaderFile, ReaderInput, Reduction};
use crate::mutate::{
    SPECIAL_COUNTS, SPECIAL_REALS, byte_mutation, line_deleted_or_duplicated, line_of,
    lines_swapped, negate, splice, truncation,
};
use crate::rng::Rng;

/// Bytes that an inserted or replaced byte is drawn from.
const BYTES: &[u8] = b"0123456789.,-+eE* \t\n%=#!EUXYZ";

/// Words a Matrix Market banner word is replaced with.
const BANNER_WORDS: &[&str] = &[
    "matrix",
    "vector",
    "coordinate",
    "array",
    "real",
    "integer",
    "complex",
    "pattern",
    "double",
    "symmetric",
    "general",
    "skew-symmetric",
    "hermitian",
    "",
    "%%MatrixMarket",
    "%MatrixMarket",
];

/// Keywords an Abaqus keyword is replaced with.
const KEYWORDS: &[&str] = &[
    "*NODE",
    "*ELEMENT",
    "*NSET",
    "*ELSET",
    "*PART",
    "*END PART",
    "*INSTANCE",
    "*END INSTANCE",
    "*ASSEMBLY",
    "*END ASSEMBLY",
    "*STEP",
    "*MATRIX GENERATE",
    "*HEADING",
    "*",
    "*UNKNOWN KEYWORD",
];

/// Parameters added to, or put in place of one of, an Abaqus keyword line's.
const PARAMETERS: &[&str] = &[
    " generate",
    " type=C3D20",
    " type=C3D4",
    " type=S4R",
    " type=XYZ",
    " type=",
    " name=",
    " name=BAR-1",
    " instance=NOPE",
    " instance=BAR-1",
    " nset=ALL",
    " elset=",
    " part=BAR",
    " internal",
];

/// DOF labels a DOF label is replaced with.
const DOF_LABELS: &[&str] = &[
    "UX", "UY", "UZ", "ROTX", "ROTY", "ROTZ", "ux", "rz", "RX", "TEMP", "PRES", "U7", "",
];

/// A mutated reader input and how it was made.
#[derive(Clone, Debug)]
pub struct ReaderMutant {
    /// The seed it was made from: its reader and files.
    pub seed: String,
    /// The input to run.
    pub input: ReaderInput,
    /// One line per mutation, each naming its file.
    pub mutations: Vec<String>,
}

/// The mutant `index` of the campaign `seed` over `corpus`.
pub fn reader_mutant(corpus: &[ReaderSeed], seed: u64, index: u64) -> ReaderMutant {
    let mut rng = Rng::for_mutant(seed, index);
    let base = rng.pick(corpus);
    let mut files: Vec<ReaderFile> = base.files.clone();
    let count = *rng.pick(&[1, 1, 1, 2, 2, 3]);
    let mut mutations = Vec::with_capacity(count);
    for _ in 0..count {
        let file = &mut files[rng.below(base.files.len())];
        let (text, what) = match rng.below(4) {
            0 | 1 => number_mutation(&file.text, &mut rng),
            2 => syntax_mutation(&file.text, &mut rng),
            _ => format_mutation(&file.text, &mut rng),
        };
        file.text = text;
        mutations.push(format!("{}: {what}", file.name));
    }
    let reduction = (base.reducible && rng.chance(1, 4))
        .then(|| *rng.pick(&[Reduction::Clamped, Reduction::FreeFree]));
    ReaderMutant {
        seed: describe(base),
        input: ReaderInput {
            reader: base.reader,
            files,
            reduction,
        },
        mutations,
    }
}

/// One number of the text replaced by a hostile value (or a syntax mutation when there
/// is none).
fn number_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let all = numbers(text);
    if all.is_empty() {
        return syntax_mutation(text, rng);
    }
    let (start, end) = *rng.pick(&all);
    let old = &text[start..end];
    let new = hostile_number(old, rng);
    let what = format!("line {}: `{old}` -> `{new}`", line_of(text, start));
    (splice(text, start, end, &new), what)
}

/// A hostile value for the number `old`: mostly of its own kind (integer or real).
fn hostile_number(old: &str, rng: &mut Rng) -> String {
    let integer = old
        .trim_start_matches(['-', '+'])
        .bytes()
        .all(|c| c.is_ascii_digit());
    if integer && rng.chance(1, 4) {
        let value: i128 = old.parse().unwrap_or(0);
        let step = if rng.chance(1, 2) { 1 } else { -1 };
        return value.saturating_add(step).to_string();
    }
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

/// The byte ranges of the numbers of `text`: a sign or a digit (or a point before a
/// digit) not inside a word, then digits, a fraction and an exponent.
pub fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let word = |i: usize| b[i].is_ascii_alphanumeric() || b[i] == b'_' || b[i] == b'.';
    let digit_at = |i: usize| b.get(i).is_some_and(u8::is_ascii_digit);
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = (digit_at(i)
            || (matches!(b[i], b'-' | b'+' | b'.') && digit_at(i + 1))
            || (matches!(b[i], b'-' | b'+') && b.get(i + 1) == Some(&b'.') && digit_at(i + 2)))
            && (i == 0 || !word(i - 1));
        if !starts {
            i += 1;
            continue;
        }
        let start = i;
        i += usize::from(matches!(b[i], b'-' | b'+'));
        while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
            i += 1;
        }
        if i < b.len() && matches!(b[i], b'e' | b'E') {
            let sign = usize::from(matches!(b.get(i + 1), Some(b'-' | b'+')));
            if digit_at(i + 1 + sign) {
                i += 1 + sign;
                while digit_at(i) {
                    i += 1;
                }
            }
        }
        out.push((start, i));
    }
    out
}

/// A line deleted, duplicated or swapped, a truncation or a byte mutation.
fn syntax_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    match rng.below(5) {
        0 if !lines.is_empty() => line_deleted_or_duplicated(&lines, rng),
        1 if lines.len() > 1 => lines_swapped(&lines, rng),
        2 => truncation(text, rng),
        _ => byte_mutation(text, rng, BYTES),
    }
}

/// The format-aware mutations `text` admits.
#[derive(Clone, Copy, Debug)]
enum FormatMutation {
    Banner,
    SizeLine,
    Keyword,
    DofLabel,
    LineEndings,
}

/// One format-aware mutation, among those the text admits.
fn format_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let banner = banner_line(text).is_some();
    let mut kinds = Vec::new();
    if banner {
        kinds.extend([FormatMutation::Banner, FormatMutation::SizeLine]);
    }
    if !keyword_lines(text).is_empty() {
        kinds.push(FormatMutation::Keyword);
    }
    if !dof_labels(text).is_empty() {
        kinds.push(FormatMutation::DofLabel);
    }
    kinds.push(FormatMutation::LineEndings);
    match rng.pick(&kinds) {
        FormatMutation::Banner => banner_mutation(text, rng),
        FormatMutation::SizeLine => size_line_mutation(text, rng),
        FormatMutation::Keyword => keyword_mutation(text, rng),
        FormatMutation::DofLabel => dof_label_mutation(text, rng),
        FormatMutation::LineEndings => line_ending_mutation(text, rng),
    }
}

/// The byte range of the Matrix Market banner (the first line, `%%MatrixMarket …`).
fn banner_line(text: &str) -> Option<(usize, usize)> {
    let end = text.find('\n').unwrap_or(text.len());
    text[..end]
        .to_ascii_lowercase()
        .starts_with("%%matrixmarket")
        .then_some((0, end))
}

/// One word of the banner replaced, deleted or doubled.
fn banner_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let (start, end) = banner_line(text).unwrap_or((0, 0));
    let line = &text[start..end];
    let mut words: Vec<&str> = line.split_whitespace().collect();
    if words.is_empty() {
        return line_ending_mutation(text, rng);
    }
    let i = rng.below(words.len());
    let old = words[i];
    let new = *rng.pick(BANNER_WORDS);
    if rng.chance(1, 4) {
        words.insert(i, old);
    } else {
        words[i] = new;
    }
    let changed = words.join(" ");
    let what = format!("line 1 (banner): `{line}` -> `{changed}`");
    (splice(text, start, end, &changed), what)
}

/// One size of the Matrix Market size line (the first line after the banner that is no
/// comment) made hostile or moved by one, or a size deleted or added.
fn size_line_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let mut at = 0;
    let mut size_line = None;
    for (k, line) in text.split_inclusive('\n').enumerate() {
        let body = line.trim();
        if k > 0 && !body.is_empty() && !body.starts_with('%') {
            size_line = Some((at, at + line.trim_end_matches(['\n', '\r']).len()));
            break;
        }
        at += line.len();
    }
    let Some((start, end)) = size_line else {
        return number_mutation(text, rng);
    };
    let line = &text[start..end];
    let mut sizes: Vec<String> = line.split_whitespace().map(str::to_string).collect();
    if sizes.is_empty() {
        return number_mutation(text, rng);
    }
    let i = rng.below(sizes.len());
    match rng.below(6) {
        0 => {
            sizes.remove(i);
        }
        1 => sizes.push(sizes[i].clone()),
        _ => sizes[i] = hostile_number(&sizes[i], rng),
    }
    let changed = sizes.join(" ");
    let what = format!(
        "line {} (sizes): `{line}` -> `{changed}`",
        line_of(text, start)
    );
    (splice(text, start, end, &changed), what)
}

/// The byte ranges of the Abaqus keyword lines (`*KEYWORD, …`; not `**` comments).
fn keyword_lines(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        let body = line.trim_end_matches(['\n', '\r']);
        if body.starts_with('*') && !body.starts_with("**") {
            out.push((at, at + body.len()));
        }
        at += line.len();
    }
    out
}

/// One keyword line's keyword replaced, a parameter replaced, added or dropped, the
/// line lower-cased, or its `*` removed.
fn keyword_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let lines = keyword_lines(text);
    let (start, end) = *rng.pick(&lines);
    let line = &text[start..end];
    let mut parts: Vec<String> = line.split(',').map(str::to_string).collect();
    match rng.below(6) {
        0 | 1 => parts[0] = rng.pick(KEYWORDS).to_string(),
        2 if parts.len() > 1 => {
            let i = 1 + rng.below(parts.len() - 1);
            parts[i] = rng.pick(PARAMETERS).to_string();
        }
        3 if parts.len() > 1 => {
            parts.remove(1 + rng.below(parts.len() - 1));
        }
        4 => parts = vec![line.to_ascii_lowercase()],
        5 => parts = vec![line[1..].to_string()],
        _ => parts.push(rng.pick(PARAMETERS).to_string()),
    }
    let changed = parts.join(",");
    let what = format!(
        "line {} (keyword): `{line}` -> `{changed}`",
        line_of(text, start)
    );
    (splice(text, start, end, &changed), what)
}

/// The byte ranges of the DOF labels (`UX` … `ROTZ`, any case, as whole words).
fn dof_labels(text: &str) -> Vec<(usize, usize)> {
    const LABELS: &[&str] = &["ux", "uy", "uz", "rotx", "roty", "rotz"];
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if !b[i].is_ascii_alphabetic() {
            i += 1;
            continue;
        }
        let start = i;
        while i < b.len() && b[i].is_ascii_alphanumeric() {
            i += 1;
        }
        let before_ok = start == 0 || !matches!(b[start - 1], b'_' | b'.' | b'-');
        if before_ok && LABELS.contains(&text[start..i].to_ascii_lowercase().as_str()) {
            out.push((start, i));
        }
    }
    out
}

/// One DOF label replaced by another or by an unknown one.
fn dof_label_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    let (start, end) = *rng.pick(&dof_labels(text));
    let old = &text[start..end];
    let new = *rng.pick(DOF_LABELS);
    let what = format!(
        "line {} (DOF label): `{old}` -> `{new}`",
        line_of(text, start)
    );
    (splice(text, start, end, new), what)
}

/// Line endings made CRLF or CR, a byte-order mark added, or the spaces of a line made
/// tabs.
fn line_ending_mutation(text: &str, rng: &mut Rng) -> (String, String) {
    match rng.below(4) {
        0 => (text.replace('\n', "\r\n"), "line endings: CRLF".into()),
        1 => (text.replace('\n', "\r"), "line endings: CR only".into()),
        2 => (format!("\u{feff}{text}"), "byte-order mark added".into()),
        _ => {
            let lines: Vec<&str> = text.split_inclusive('\n').collect();
            if lines.is_empty() {
                return (format!("\u{feff}{text}"), "byte-order mark added".into());
            }
            let i = rng.below(lines.len());
            let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            out[i] = out[i].replace(' ', "\t");
            (out.concat(), format!("line {}: spaces made tabs", i + 1))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::readers::corpus::{default_import_data_dir, load_reader_corpus};

    #[test]
    fn numbers_are_found_with_signs_fractions_and_exponents_but_not_inside_words() {
        let text = "BAR-1.1,2, -3.5e-002 C3D8 .5 +7E+3 x1 1.2";
        let found: Vec<&str> = numbers(text).iter().map(|&(a, b)| &text[a..b]).collect();
        assert_eq!(found, ["1.1", "2", "-3.5e-002", ".5", "+7E+3", "1.2"]);
    }

    #[test]
    fn the_same_seed_and_index_give_the_same_mutant() {
        let corpus = load_reader_corpus(&default_import_data_dir()).unwrap();
        for index in 0..300 {
            let (a, b) = (
                reader_mutant(&corpus, 4, index),
                reader_mutant(&corpus, 4, index),
            );
            assert_eq!((a.input, a.mutations), (b.input, b.mutations));
        }
    }

    #[test]
    fn every_kind_of_mutation_is_drawn() {
        let corpus = load_reader_corpus(&default_import_data_dir()).unwrap();
        let all: Vec<String> = (0..4000)
            .flat_map(|i| reader_mutant(&corpus, 1, i).mutations)
            .collect();
        for what in [
            "(banner)",
            "(sizes)",
            "(keyword)",
            "(DOF label)",
            "CRLF",
            "-> `NaN`",
            "-> `18446744073709551615`",
            "deleted",
            "truncated",
        ] {
            assert!(all.iter().any(|m| m.contains(what)), "{what} never drawn");
        }
        let reduced = (0..400)
            .filter(|&i| reader_mutant(&corpus, 1, i).input.reduction.is_some())
            .count();
        assert!(reduced > 20, "{reduced} of 400 mutants reduced");
    }
}
