//! Wavefront OBJ: vertex positions (`v`) and faces (`f`, polygons fanned into triangles).
//!
//! Written by hand: we need only positions and faces, and errors that give the line number of a
//! bad index or number, which the general-purpose loaders do not report.

use prehensile_core::math::Point3;

use crate::FormatError;

/// Parses OBJ text into positions and triangles. Negative (relative) indices are supported.
pub fn parse_obj(
    text: &str,
    source_name: &str,
) -> Result<(Vec<Point3>, Vec<[usize; 3]>), FormatError> {
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    // One face's vertex indices, reused from face to face.
    let mut face = Vec::with_capacity(4);
    for (n, raw) in text.lines().enumerate() {
        let line_no = n + 1;
        let err = |reason: String| FormatError::at(source_name, format!("line {line_no}"), reason);
        // Byte searches: `str::find(char)` costs a searcher per call, and this runs on every
        // line and every face word (half the reader's time on a 16k-triangle scan). `#` and `/`
        // are ASCII, so a byte match is a char boundary.
        let line = ascii_before(raw, b'#');
        // OBJ separates with spaces and tabs; the ASCII split is several times faster than the
        // Unicode one, and any other space left in a word makes it an error that names it.
        let mut words = line.split_ascii_whitespace();
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
                vertices.push(Point3::from(p));
            }
            Some("f") => {
                face.clear();
                for w in words {
                    let first = ascii_before(w, b'/');
                    let i: i64 = first
                        .parse()
                        .map_err(|_| err(format!("'{w}' is not a vertex index")))?;
                    let count = vertices.len() as i64;
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
                    triangles.push([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if triangles.is_empty() {
        return Err(FormatError::new(
            source_name,
            "no faces found; is this an OBJ mesh?",
        ));
    }
    Ok((vertices, triangles))
}

/// `text` up to the first `byte` (an ASCII character), or all of it.
fn ascii_before(text: &str, byte: u8) -> &str {
    match text.bytes().position(|b| b == byte) {
        Some(end) => &text[..end],
        None => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn out_of_range_index_names_the_line() {
        let e = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "bad.obj").unwrap_err();
        assert_eq!(e.location.as_deref(), Some("line 4"));
        assert!(e.reason.contains("vertex 7"), "{e}");
        let e = parse_obj("v 0 0 nan_\n", "bad.obj").unwrap_err();
        assert_eq!(e.location.as_deref(), Some("line 1"));
    }
}
