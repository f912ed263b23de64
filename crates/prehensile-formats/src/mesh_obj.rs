//! Wavefront OBJ: vertex positions (`v`) and faces (`f`, polygons fanned into triangles).
//!
//! Written by hand: we need only positions and faces, and errors that give the line number of a
//! bad index or number, which the general-purpose loaders do not report. A large file is read in
//! pieces side by side (rayon); see [`parse_obj`].

use prehensile_core::math::Point3;
use rayon::prelude::*;

use crate::FormatError;

/// The least length of each piece a file is read in side by side: below it a thread's start
/// and the pieces' joining cost more than they save.
const PIECE_BYTES: usize = 256 * 1024;

/// Parses OBJ text into positions and triangles. Negative (relative) indices are supported.
///
/// A large file is cut into pieces at line ends, read side by side. A piece after the first
/// does not know how many vertices come before it until the pieces before it are read, so it
/// checks its faces' indices afterwards: it keeps the most by which an index runs past the
/// vertices it has read itself. A piece whose check fails, or that met a bad line or a relative
/// index, is read again knowing how many come before it: that finds the first bad line, and
/// says what is wrong with it, as one pass over the whole file would.
pub fn parse_obj(
    text: &str,
    source_name: &str,
) -> Result<(Vec<Point3>, Vec<[usize; 3]>), FormatError> {
    let pieces = pieces(text, rayon::current_num_threads(), PIECE_BYTES);
    parse_pieces(&pieces, source_name)
}

/// [`parse_obj`] of the text cut into `pieces`.
fn parse_pieces(
    pieces: &[&str],
    source_name: &str,
) -> Result<(Vec<Point3>, Vec<[usize; 3]>), FormatError> {
    let read: Vec<_> = pieces
        .par_iter()
        .enumerate()
        .map(|(k, piece)| read_piece(piece, (k == 0).then_some(0)))
        .collect();
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (k, (piece, read)) in pieces.iter().zip(read).enumerate() {
        let before = vertices.len();
        let read = match read {
            Ok(read) if read.reach_past_own < before as i64 => Ok(read),
            _ => read_piece(piece, Some(before)),
        };
        let read = read.map_err(|(line, reason)| {
            let lines_before: usize = pieces[..k].iter().map(|p| p.lines().count()).sum();
            FormatError::at(source_name, format!("line {}", lines_before + line), reason)
        })?;
        append(&mut vertices, read.vertices);
        append(&mut triangles, read.triangles);
    }
    if triangles.is_empty() {
        return Err(FormatError::new(
            source_name,
            "no faces found; is this an OBJ mesh?",
        ));
    }
    Ok((vertices, triangles))
}

/// `from` after `into`'s items, moved instead of copied when `into` is empty.
fn append<T>(into: &mut Vec<T>, from: Vec<T>) {
    if into.is_empty() {
        *into = from;
    } else {
        into.extend(from);
    }
}

/// `text` cut into at most `most` pieces of at least `least_bytes` each, every cut just after a
/// line's end, so that each line lies whole in one piece.
fn pieces(text: &str, most: usize, least_bytes: usize) -> Vec<&str> {
    let count = (text.len() / least_bytes.max(1)).clamp(1, most.max(1));
    let mut pieces = Vec::with_capacity(count);
    let mut rest = text;
    for left in (1..count).rev() {
        // This piece's share of the rest, and `left` pieces' after it.
        let aim = rest.len() / (left + 1);
        let Some(end) = rest.as_bytes()[aim..].iter().position(|&b| b == b'\n') else {
            break;
        };
        let (piece, after) = rest.split_at(aim + end + 1);
        pieces.push(piece);
        rest = after;
    }
    pieces.push(rest);
    pieces
}

/// A piece of a file, read.
struct Piece {
    vertices: Vec<Point3>,
    /// Triangles, their indices over the whole file.
    triangles: Vec<[usize; 3]>,
    /// For a piece read without knowing the vertices before it, the most by which a face's
    /// (zero-based) index runs past the vertices the piece had read before that face:
    /// `i64::MIN` when there is no face, `i64::MAX` when a relative index stopped the reading.
    /// The indices are good when more than this many vertices come before the piece. For a
    /// piece read knowing them, `i64::MIN`: its indices were checked as they came.
    reach_past_own: i64,
}

/// Reads `piece`, its first line after `vertices_before` vertices when that is known; or the
/// first bad line's number within the piece (from 1) and what is wrong with it. Without the
/// count, indices are checked afterwards ([`Piece::reach_past_own`]), and a relative index
/// stops the reading.
fn read_piece(piece: &str, vertices_before: Option<usize>) -> Result<Piece, (usize, String)> {
    let mut read = Piece {
        vertices: Vec::new(),
        triangles: Vec::new(),
        reach_past_own: i64::MIN,
    };
    // One face's vertex indices, reused from face to face.
    let mut face = Vec::with_capacity(4);
    for (n, line) in piece.lines().enumerate() {
        let err = |reason: String| (n + 1, reason);
        let mut words = Words::of(line);
        match words.next() {
            Some("v") => {
                let mut p = [0.0; 3];
                for c in p.iter_mut() {
                    let w = words
                        .next()
                        .ok_or_else(|| err("a vertex needs three coordinates".into()))?;
                    *c = w
                        .parse()
                        .map_err(|_| err(format!("'{w}' is not a number")))?;
                }
                read.vertices.push(Point3::from(p));
            }
            Some("f") => {
                face.clear();
                let own = read.vertices.len() as i64;
                for w in words {
                    let i = vertex_index(w)
                        .ok_or_else(|| err(format!("'{w}' is not a vertex index")))?;
                    let Some(before) = vertices_before else {
                        // A relative index (or a 0, which the reading again names) needs the
                        // count before.
                        if i <= 0 {
                            read.reach_past_own = i64::MAX;
                            return Ok(read);
                        }
                        read.reach_past_own = read.reach_past_own.max(i - 1 - own);
                        face.push(i as usize - 1);
                        continue;
                    };
                    let count = before as i64 + own;
                    let resolved = if i > 0 { i - 1 } else { count + i };
                    if i == 0 || resolved < 0 || resolved >= count {
                        return Err(err(format!(
                            "face refers to vertex {i}, but only {count} vertices are defined before this line"
                        )));
                    }
                    face.push(resolved as usize);
                }
                if face.len() < 3 {
                    return Err(err(format!(
                        "a face needs at least 3 vertices, this one has {}",
                        face.len()
                    )));
                }
                for k in 1..face.len() - 1 {
                    read.triangles.push([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(read)
}

/// The position index of a face's word (`7`, `7/1`, `-2//3`): its text before any `/`, an
/// integer with an optional sign.
fn vertex_index(word: &str) -> Option<i64> {
    let first = match word.as_bytes().iter().position(|&b| b == b'/') {
        Some(end) => &word[..end],
        None => word,
    };
    first.parse().ok()
}

/// The words of a line before any `#`, split at ASCII spaces (OBJ separates with spaces and
/// tabs; any other space left in a word makes it an error that names it). One pass over the
/// bytes: the standard library's splitting and searching cost a searcher per call and half the
/// reader's time on a 16k-triangle scan. The cuts are at ASCII bytes, so on char boundaries.
struct Words<'a> {
    line: &'a str,
    at: usize,
}

impl<'a> Words<'a> {
    fn of(line: &'a str) -> Self {
        Self { line, at: 0 }
    }
}

impl<'a> Iterator for Words<'a> {
    type Item = &'a str;

    fn next(&mut self) -> Option<&'a str> {
        let bytes = self.line.as_bytes();
        let mut start = self.at;
        while start < bytes.len() && bytes[start].is_ascii_whitespace() {
            start += 1;
        }
        let mut end = start;
        while end < bytes.len() && !bytes[end].is_ascii_whitespace() && bytes[end] != b'#' {
            end += 1;
        }
        // A `#` ends the line's words.
        self.at = if end < bytes.len() && bytes[end] == b'#' {
            bytes.len()
        } else {
            end
        };
        (end > start).then(|| &self.line[start..end])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn quads_are_fanned_and_negative_indices_work() {
        let (v, t) = parse_obj(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\n",
            "q.obj",
        )
        .unwrap();
        assert_eq!(v.len(), 4);
        assert_eq!(t, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn comments_tabs_and_slashes_are_read_and_other_spaces_named() {
        let text = "# a square and a triangle\nv 0 0 0 # origin\nv\t1 0 0\nv 1 1 0\nv 0 1 0\n\
                    f 1/1/1 2//2 3/3 4\nf 4 1 3 # again\n";
        let (v, t) = parse_obj(text, "s.obj").unwrap();
        assert_eq!(v[1], Point3::new(1.0, 0.0, 0.0));
        assert_eq!(t, vec![[0, 1, 2], [0, 2, 3], [3, 0, 2]]);
        // A no-break space is not a separator in OBJ: the word that holds it is named.
        let e = parse_obj("v 0 0\u{a0}1\n", "nbsp.obj").unwrap_err();
        assert!(e.reason.contains("'0\u{a0}1' is not a number"), "{e}");
    }

    /// A small OBJ file: vertices; faces whose indices are absolute or relative, mostly among
    /// the vertices read so far and now and then one past them; and, rarely, a zero or
    /// malformed index, a bad number or a comment.
    fn obj_text() -> impl Strategy<Value = String> {
        // Each line: a kind, and per face word how far back from the vertex count it reaches.
        let line = (
            0u8..200,
            prop::collection::vec(-4i64..=0, 3..6),
            any::<bool>(),
        );
        prop::collection::vec(line, 1..60).prop_map(|lines| {
            let mut text = String::new();
            let mut count = 0i64;
            for (kind, reach, relative) in lines {
                let line = match kind {
                    0..=99 => {
                        count += 1;
                        format!("v {kind} {count}.5 -{count}e-1")
                    }
                    100..=193 => {
                        let words: Vec<String> = reach
                            .iter()
                            .map(|&r| match (relative, kind) {
                                (_, 190..) => (count + 1).to_string(),
                                (true, _) => format!("{}/2", r - 1),
                                (false, _) => (count + r).max(1).to_string(),
                            })
                            .collect();
                        format!("f {}", words.join(" "))
                    }
                    194..=196 => "# a comment".into(),
                    197 => "v 1 2 oops".into(),
                    198 => "f 1 x 2".into(),
                    _ => "f 0 1 2".into(),
                };
                text.push_str(&line);
                text.push('\n');
            }
            text
        })
    }

    proptest::proptest! {
        #[test]
        fn a_file_read_in_pieces_reads_as_in_one(
            text in obj_text(),
            most in 2usize..6,
            least in 1usize..200,
        ) {
            let whole = parse_pieces(&[&text], "p.obj");
            let cut = pieces(&text, most, least);
            proptest::prop_assert_eq!(cut.concat(), text.clone());
            let in_pieces = parse_pieces(&cut, "p.obj");
            proptest::prop_assert_eq!(
                format!("{in_pieces:?}"),
                format!("{whole:?}"),
                "cut into {} pieces",
                cut.len()
            );
        }
    }

    #[test]
    fn a_large_file_names_a_bad_line_far_into_it() {
        // Over 1 MB: read in pieces wherever the pool has two threads or more.
        let mut text = String::new();
        for k in 0..30_000 {
            text.push_str(&format!("v {k} {k}.25 -{k}.5\n"));
        }
        for k in 1..29_998 {
            text.push_str(&format!("f {k} {} {}\n", k + 1, k + 2));
        }
        let (v, t) = parse_obj(&text, "big.obj").unwrap();
        assert_eq!(
            (v.len(), t.len(), t[29_996]),
            (30_000, 29_997, [29_996, 29_997, 29_998])
        );
        let late = format!("{text}f -1 -2 -3\nf 1 2 30001\n");
        let e = parse_obj(&late, "big.obj").unwrap_err();
        assert_eq!(e.location.as_deref(), Some("line 59999"), "{e}");
        assert!(e.reason.contains("vertex 30001"), "{e}");
    }

    #[test]
    fn out_of_range_index_names_the_line() {
        let e = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "bad.obj").unwrap_err();
        assert_eq!(e.location.as_deref(), Some("line 4"));
        assert!(e.reason.contains("vertex 7"), "{e}");
        let e = parse_obj("v 0 0 nan_\n", "bad.obj").unwrap_err();
        assert_eq!(e.location.as_deref(), Some("line 1"));
    }
}
