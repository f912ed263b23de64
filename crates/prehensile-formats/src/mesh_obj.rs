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
    for (n, raw) in text.lines().enumerate() {
        let line_no = n + 1;
        let err = |reason: String| FormatError::at(source_name, format!("line {line_no}"), reason);
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
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
                let mut face = Vec::with_capacity(4);
                for w in words {
                    let first = w.split('/').next().unwrap_or("");
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
    fn out_of_range_index_names_the_line() {
        let e = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "bad.obj").unwrap_err();
        assert_eq!(e.location.as_deref(), Some("line 4"));
        assert!(e.reason.contains("vertex 7"), "{e}");
        let e = parse_obj("v 0 0 nan_\n", "bad.obj").unwrap_err();
        assert_eq!(e.location.as_deref(), Some("line 1"));
    }
}
