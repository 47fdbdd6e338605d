//! The line of a field in a scene file, for the validation errors.
//!
//! A refusal names its field by a path such as `bodies[crank1].markers[A].position[0]`:
//! keys (`bodies`, `markers`, `position`; enum variants such as `Rigid` or `SpinUp` count as
//! keys) and, in brackets, the `name` of an item of a list (or an index, which is skipped).
//! [`line_of`] follows the path through the RON text: each key is looked for after the
//! previous match, as a whole word followed by `:` or `(` outside comments and strings; each
//! item by its `name: "…"`, after which the search stays inside that item's parentheses (so
//! that a field the item omits is not found in the next item). It is a heuristic: when a
//! part of the path is not found, the error carries no line rather than a wrong one.

/// The 1-based line of the field `path` in the scene text `text`, if it can be found.
pub fn line_of(text: &str, path: &str) -> Option<u32> {
    let code = Code::new(text);
    let (found, _, _) = code.locate(path)?;
    line_at(text, found)
}

/// The 1-based line of the second item named `name` in the list at `list` (a name given
/// twice: the line of the repeat, not of the original).
pub fn line_of_repeated(text: &str, list: &str, name: &str) -> Option<u32> {
    let code = Code::new(text);
    let (_, pos, limit) = code.locate(list)?;
    let first = code.find_item(name, pos, limit)?;
    let second = code.find_item(name, first + 4, limit)?;
    line_at(text, second)
}

/// The 1-based line of byte `at`.
fn line_at(text: &str, at: usize) -> Option<u32> {
    let newlines = text.as_bytes()[..at]
        .iter()
        .filter(|&&c| c == b'\n')
        .count();
    u32::try_from(newlines + 1).ok()
}

impl Code {
    /// Follow `path`: the start of its last part found, and the range after it that the
    /// search of a further part is confined to.
    fn locate(&self, path: &str) -> Option<(usize, usize, usize)> {
        let code = self;
        let mut pos = 0;
        let mut limit = code.bytes.len();
        let mut found = None;
        for segment in segments(path) {
            match segment {
                Segment::Key(key) => {
                    let at = code.find_key(key, pos, limit)?;
                    pos = at + key.len();
                    found = Some(at);
                }
                Segment::Item(name) => match code.find_item(name, pos, limit) {
                    Some(at) => {
                        limit = code.enclosing_end(at).unwrap_or(limit);
                        pos = at;
                        found = Some(at);
                    }
                    // An index into a list of numbers or of unnamed items: stay on the key.
                    None if name.parse::<usize>().is_ok() => {}
                    None => return None,
                },
            }
        }
        Some((found?, pos, limit))
    }
}

/// One part of a field path.
#[derive(Debug, PartialEq)]
enum Segment<'a> {
    /// A field name or enum variant.
    Key(&'a str),
    /// The name (or index) of a list item.
    Item(&'a str),
}

/// `a[b].c.d[0]` → Key(a), Item(b), Key(c), Key(d), Item(0).
fn segments(path: &str) -> Vec<Segment<'_>> {
    let mut out = Vec::new();
    let mut rest = path;
    while !rest.is_empty() {
        if let Some(inner) = rest.strip_prefix('[') {
            let end = inner.find(']').unwrap_or(inner.len());
            out.push(Segment::Item(&inner[..end]));
            rest = inner.get(end + 1..).unwrap_or("");
        } else if let Some(r) = rest.strip_prefix('.') {
            rest = r;
        } else {
            let end = rest.find(['.', '[']).unwrap_or(rest.len());
            out.push(Segment::Key(&rest[..end]));
            rest = &rest[end..];
        }
    }
    out
}

/// The scene text with its comments blanked (newlines kept, so offsets and lines stay)
/// and a mark on every byte inside a string literal.
struct Code {
    bytes: Vec<u8>,
    in_string: Vec<bool>,
}

impl Code {
    fn new(text: &str) -> Code {
        let src = text.as_bytes();
        let mut bytes = src.to_vec();
        let mut in_string = vec![false; src.len()];
        let mut i = 0;
        while i < src.len() {
            match (src[i], src.get(i + 1)) {
                (b'/', Some(b'/')) => {
                    while i < src.len() && src[i] != b'\n' {
                        bytes[i] = b' ';
                        i += 1;
                    }
                }
                (b'/', Some(b'*')) => {
                    let mut depth = 0usize;
                    while i < src.len() {
                        if src[i..].starts_with(b"/*") {
                            depth += 1;
                            bytes[i] = b' ';
                            bytes[i + 1] = b' ';
                            i += 2;
                        } else if src[i..].starts_with(b"*/") {
                            depth -= 1;
                            bytes[i] = b' ';
                            bytes[i + 1] = b' ';
                            i += 2;
                            if depth == 0 {
                                break;
                            }
                        } else {
                            if src[i] != b'\n' {
                                bytes[i] = b' ';
                            }
                            i += 1;
                        }
                    }
                }
                (b'"', _) => {
                    i += 1;
                    while i < src.len() && src[i] != b'"' {
                        in_string[i] = true;
                        i += if src[i] == b'\\' { 2 } else { 1 };
                    }
                    i += 1;
                }
                _ => i += 1,
            }
        }
        Code { bytes, in_string }
    }

    fn is_word(c: u8) -> bool {
        c.is_ascii_alphanumeric() || c == b'_'
    }

    /// The first byte after `from` that is not white space.
    fn skip_space(&self, from: usize) -> usize {
        let mut j = from;
        while j < self.bytes.len() && self.bytes[j].is_ascii_whitespace() {
            j += 1;
        }
        j
    }

    /// The start of `key` as a whole word followed by `:` or `(`, in `from..limit`.
    fn find_key(&self, key: &str, from: usize, limit: usize) -> Option<usize> {
        let k = key.as_bytes();
        if k.is_empty() {
            return None;
        }
        let end = limit.min(self.bytes.len());
        (from..end.saturating_sub(k.len() - 1)).find(|&i| {
            !self.in_string[i]
                && self.bytes[i..].starts_with(k)
                && (i == 0 || !Self::is_word(self.bytes[i - 1]))
                && matches!(
                    self.bytes.get(self.skip_space(i + k.len())),
                    Some(b':' | b'(')
                )
        })
    }

    /// The start of the `name` key whose value is the string `name`, in `from..limit`.
    fn find_item(&self, name: &str, from: usize, limit: usize) -> Option<usize> {
        let mut pos = from;
        while let Some(at) = self.find_key("name", pos, limit) {
            let colon = self.skip_space(at + 4);
            let quote = self.skip_space(colon + 1);
            let value = self.bytes.get(quote + 1..)?;
            if self.bytes[quote] == b'"'
                && value.starts_with(name.as_bytes())
                && value.get(name.len()) == Some(&b'"')
            {
                return Some(at);
            }
            pos = at + 4;
        }
        None
    }

    /// The end of the parentheses that enclose byte `at` (the item's struct).
    fn enclosing_end(&self, at: usize) -> Option<usize> {
        let mut depth = 0i64;
        let mut open = None;
        for i in (0..at).rev() {
            if self.in_string[i] {
                continue;
            }
            match self.bytes[i] {
                b')' | b']' => depth += 1,
                b'(' | b'[' if depth > 0 => depth -= 1,
                b'(' | b'[' => {
                    open = Some(i);
                    break;
                }
                _ => {}
            }
        }
        let mut depth = 0i64;
        for i in open? + 1..self.bytes.len() {
            if self.in_string[i] {
                continue;
            }
            match self.bytes[i] {
                b'(' | b'[' => depth += 1,
                b')' | b']' if depth == 0 => return Some(i),
                b')' | b']' => depth -= 1,
                _ => {}
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = r#"(
    name: "x", // bodies: not here
    bodies: [
        (
            name: "a",
            markers: [(name: "P", position: [0.0, 0.0])],
        ),
        (
            name: "b",
            velocity: (linear: [1.0, 0.0]),
            markers: [
                (name: "P", position: [1.0, 0.0]),
                (name: "Q", position: [2.0, 0.0]),
            ],
        ),
    ],
    solver: (step: 1e-3, duration: 1.0),
)"#;

    #[test]
    fn a_path_is_followed_through_items_and_keys() {
        assert_eq!(line_of(SCENE, "bodies[b].markers[Q].position[0]"), Some(13));
        assert_eq!(line_of(SCENE, "bodies[a].markers[P].position[1]"), Some(6));
        assert_eq!(line_of(SCENE, "solver.duration"), Some(17));
        assert_eq!(line_of(SCENE, "bodies[b].velocity.linear[0]"), Some(10));
    }

    #[test]
    fn a_field_an_item_omits_is_not_found_in_the_next_item() {
        assert_eq!(line_of(SCENE, "bodies[a].velocity.linear[0]"), None);
        assert_eq!(line_of(SCENE, "bodies[c].origin"), None);
        assert_eq!(line_of("", "solver.step"), None);
    }

    #[test]
    fn a_repeated_name_is_found_where_it_repeats() {
        assert_eq!(line_of_repeated(SCENE, "bodies[b].markers", "P"), None);
        let twice = SCENE.replace(r#"(name: "Q""#, r#"(name: "P""#);
        assert_eq!(line_of_repeated(&twice, "bodies[b].markers", "P"), Some(13));
        assert_eq!(line_of_repeated(&twice, "bodies[a].markers", "P"), None);
    }
}
