//! Formatting a document on request: on each line made only of words and
//! comments, the letters upper case, one space between words, no spaces
//! at the end, and the `N` words renumbered (10, 20, …), removed or kept.
//! Any other line (expressions, keywords, assignments, calls) is left as
//! written but for its trailing spaces. Text in, text out: whether the
//! tool path stayed the same is checked by the caller
//! ([`super::analysis::formatted`]).

/// What becomes of the `N` words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Numbers {
    /// 10, 20, … on the lines that have one.
    Renumber,
    Remove,
    Keep,
}

/// A piece of a line of words.
enum Piece<'a> {
    /// The letter, upper case, and the number as written.
    Word(char, &'a str),
    Comment(&'a str),
}

/// `text` formatted; `egc`: read as `.egc` (where `;` ends a statement
/// and `//` starts a comment). The `N` words are kept when the program
/// jumps to them (`GOTO`, `M99 P…`).
pub fn format(text: &str, egc: bool, numbers: Numbers) -> String {
    let jumps = text.lines().any(|l| {
        let upper = l.to_ascii_uppercase();
        upper.contains("GOTO") || upper.contains("M99") && upper.contains('P')
    });
    let numbers = if jumps { Numbers::Keep } else { numbers };
    let mut out = String::with_capacity(text.len());
    let mut next = 10u64;
    for line in text.split_inclusive('\n') {
        let (body, end) = match line.strip_suffix("\r\n") {
            Some(body) => (body, "\r\n"),
            None => match line.strip_suffix('\n') {
                Some(body) => (body, "\n"),
                None => (line, ""),
            },
        };
        match pieces(body, egc) {
            Some((block_delete, pieces)) if !pieces.is_empty() => {
                out.push_str(&written(block_delete, &pieces, numbers, &mut next));
            }
            _ => out.push_str(body.trim_end()),
        }
        out.push_str(end);
    }
    out
}

/// A line of words written again.
fn written(block_delete: bool, pieces: &[Piece<'_>], numbers: Numbers, next: &mut u64) -> String {
    let mut parts: Vec<String> = Vec::with_capacity(pieces.len() + 1);
    if block_delete {
        parts.push("/".into());
    }
    let mut numbered = false;
    for piece in pieces {
        match piece {
            Piece::Word('N', _) if numbers == Numbers::Remove => {}
            Piece::Word('N', _) if numbers == Numbers::Renumber => {
                if !numbered {
                    parts.push(format!("N{next}"));
                    *next += 10;
                    numbered = true;
                }
            }
            Piece::Word(letter, number) => parts.push(format!("{letter}{number}")),
            Piece::Comment(c) => parts.push(c.to_string()),
        }
    }
    let line = parts.join(" ");
    // A block-delete slash stays against the line's first word.
    match line.strip_prefix("/ ") {
        Some(rest) => format!("/{rest}"),
        None => line,
    }
}

/// The words and comments of `line`, and whether it starts with a
/// block-delete `/`; `None` when it holds anything else.
fn pieces(line: &str, egc: bool) -> Option<(bool, Vec<Piece<'_>>)> {
    let bytes = line.as_bytes();
    let mut i = 0;
    let mut out = Vec::new();
    let mut block_delete = false;
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b' ' | b'\t' => i += 1,
            b'/' if out.is_empty()
                && !block_delete
                && !(egc && bytes.get(i + 1) == Some(&b'/')) =>
            {
                block_delete = true;
                i += 1;
            }
            b'(' => {
                let end = comment_end(bytes, i, !egc)?;
                out.push(Piece::Comment(&line[i..end]));
                i = end;
            }
            b';' if !egc => {
                out.push(Piece::Comment(line[i..].trim_end()));
                i = bytes.len();
            }
            b'/' if egc && bytes.get(i + 1) == Some(&b'/') => {
                out.push(Piece::Comment(line[i..].trim_end()));
                i = bytes.len();
            }
            c if c.is_ascii_alphabetic() => {
                let start = i + 1;
                let mut end = start;
                if matches!(bytes.get(end), Some(b'+' | b'-')) {
                    end += 1;
                }
                let digits_from = end;
                while bytes
                    .get(end)
                    .is_some_and(|b| b.is_ascii_digit() || *b == b'.')
                {
                    end += 1;
                }
                let number = &line[start..end];
                if !line[digits_from..end].bytes().any(|b| b.is_ascii_digit())
                    || number.matches('.').count() > 1
                    || bytes.get(end).is_some_and(|b| *b == b'_')
                {
                    return None;
                }
                out.push(Piece::Word(c.to_ascii_uppercase() as char, number));
                i = end;
            }
            _ => return None,
        }
    }
    Some((block_delete, out))
}

/// The end of the comment opening at `start` (past its `)`); `nested`:
/// plain G-code's `(Drill (R))`.
fn comment_end(bytes: &[u8], start: usize, nested: bool) -> Option<usize> {
    let mut depth = 0;
    for (i, &b) in bytes.iter().enumerate().skip(start) {
        match b {
            b'(' if nested || depth == 0 => depth += 1,
            b')' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i + 1);
                }
            }
            _ => {}
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_are_spaced_and_upper_case_and_numbers_renumbered() {
        let text =
            "%\nn5 g0x0 y0   z5\r\nN7 g1 z-1 f100 (cut (deep))\n  g1  x10.  \n/n9 G1 Y5 ; end\n\
                    #<a> = 2\no100 sub\n";
        let done = format(text, false, Numbers::Renumber);
        assert_eq!(
            done,
            "%\nN10 G0 X0 Y0 Z5\r\nN20 G1 Z-1 F100 (cut (deep))\nG1 X10.\n/N30 G1 Y5 ; end\n\
             #<a> = 2\no100 sub\n"
        );
        let removed = format(text, false, Numbers::Remove);
        assert!(removed.starts_with("%\nG0 X0 Y0 Z5\r\nG1 Z-1"), "{removed}");
        // A program that jumps to its labels keeps them.
        let jumping = "N10 G0 X1\nGOTO 10\n";
        assert_eq!(format(jumping, false, Numbers::Renumber), jumping);
    }

    #[test]
    fn egc_semicolons_and_names_are_left_alone() {
        let text = "g1 x1; y2\nDepth = 2\nPocket 10 10 2\ng0 z5 // up\n";
        assert_eq!(
            format(text, true, Numbers::Renumber),
            "g1 x1; y2\nDepth = 2\nPocket 10 10 2\nG0 Z5 // up\n"
        );
    }
}
