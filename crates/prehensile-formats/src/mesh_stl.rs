//! STL, binary and ascii. Which one is decided as robust readers do: a file whose length is
//! exactly 84 + 50 × the header's triangle count is binary (even when its header starts with
//! `solid`, as many exporters write); otherwise a file starting with `solid` is ascii. The ascii
//! reader is ours (the `stl_io` crate refused valid files: `solid` with no name, blank lines
//! first, upper-case keywords), accepts keywords in any case, and names the line of any error.

use prehensile_core::math::Point3;

use crate::FormatError;

/// Positions (three per triangle, welded later) and triangles.
type Soup = (Vec<Point3>, Vec<[usize; 3]>);

/// Parses STL bytes into positions and triangles.
pub fn parse_stl(bytes: &[u8], source_name: &str) -> Result<Soup, FormatError> {
    let declared = (bytes.len() >= 84)
        .then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64);
    let soup = match declared {
        Some(count) if bytes.len() as u64 == 84 + 50 * count => binary(bytes, count as usize),
        _ if starts_with_solid(bytes) => ascii(bytes, source_name)?,
        Some(count) => {
            return Err(FormatError::at(
                source_name,
                "header",
                format!(
                    "the header declares {count} triangles ({} bytes) but the file has {} bytes, and it does not start with 'solid' as an ascii STL does; the file is truncated or not an STL",
                    84 + 50 * count,
                    bytes.len()
                ),
            ))
        }
        None => {
            return Err(FormatError::new(
                source_name,
                format!("{} bytes is too short for a binary STL (header alone is 84 bytes) and it does not start with 'solid'; the file is truncated", bytes.len()),
            ))
        }
    };
    if soup.1.is_empty() {
        return Err(FormatError::new(source_name, "the STL has no triangles"));
    }
    Ok(soup)
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let t = bytes.trim_ascii_start();
    t.len() >= 5 && t[..5].eq_ignore_ascii_case(b"solid")
}

/// 50 bytes per triangle after the 84-byte header: normal, three corners, attribute.
fn binary(bytes: &[u8], count: usize) -> Soup {
    let float = |at: usize| {
        f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]) as f64
    };
    let mut positions = Vec::with_capacity(3 * count);
    for t in 0..count {
        let base = 84 + 50 * t + 12;
        for k in 0..3 {
            let at = base + 12 * k;
            positions.push(Point3::new(float(at), float(at + 4), float(at + 8)));
        }
    }
    let triangles = (0..count).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    (positions, triangles)
}

/// `solid … facet normal … outer loop, vertex ×3, endloop, endfacet … endsolid`, keywords in any
/// case; several solids may follow each other.
fn ascii(bytes: &[u8], source_name: &str) -> Result<Soup, FormatError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| FormatError::new(source_name, format!("an ascii STL must be text: {e}")))?;
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut in_loop: Option<(usize, usize)> = None; // (line, corners so far)
    let mut ended = true;
    for (n, line) in text.lines().enumerate() {
        let at = || format!("line {}", n + 1);
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword.to_ascii_lowercase().as_str() {
            "solid" => ended = false,
            "endsolid" => ended = true,
            "facet" | "endfacet" => {}
            "outer" => in_loop = Some((n + 1, 0)),
            "vertex" => {
                let Some((_, corners)) = in_loop.as_mut() else {
                    return Err(FormatError::at(source_name, at(), "a vertex outside 'outer loop'"));
                };
                let xyz: Vec<f64> = words
                    .map(|w| w.parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| FormatError::at(source_name, at(), "a vertex needs three numbers"))?;
                let [x, y, z] = xyz[..] else {
                    return Err(FormatError::at(source_name, at(), "a vertex needs three numbers"));
                };
                positions.push(Point3::new(x, y, z));
                *corners += 1;
            }
            "endloop" => match in_loop.take() {
                Some((_, 3)) => {
                    let k = positions.len();
                    triangles.push([k - 3, k - 2, k - 1]);
                }
                Some((start, corners)) => {
                    return Err(FormatError::at(
                        source_name,
                        format!("line {start}"),
                        format!("a facet has {corners} corners; STL facets are triangles"),
                    ))
                }
                None => return Err(FormatError::at(source_name, at(), "'endloop' without 'outer loop'")),
            },
            other => {
                return Err(FormatError::at(
                    source_name,
                    at(),
                    format!("unknown keyword '{other}'; an ascii STL has solid, facet, outer loop, vertex, endloop, endfacet, endsolid"),
                ))
            }
        }
    }
    if in_loop.is_some() || !ended {
        return Err(FormatError::new(
            source_name,
            "the file ends inside a facet or solid; it is truncated",
        ));
    }
    Ok((positions, triangles))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary(tris: u32, extra: &[u8]) -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b.extend_from_slice(&tris.to_le_bytes());
        b.extend_from_slice(extra);
        b
    }

    #[test]
    fn binary_triangle_is_read() {
        let mut tri = vec![0u8; 12];
        for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
            for c in v {
                tri.extend_from_slice(&c.to_le_bytes());
            }
        }
        tri.extend_from_slice(&[0, 0]);
        let (v, t) = parse_stl(&binary(1, &tri), "t.stl").unwrap();
        assert_eq!((v.len(), t.len()), (3, 1));
    }

    #[test]
    fn truncated_and_absurd_counts_are_errors() {
        let e = parse_stl(&binary(1, &[0u8; 20]), "t.stl").unwrap_err();
        assert!(e.reason.contains("truncated"), "{e}");
        let e = parse_stl(&binary(u32::MAX, &[]), "t.stl").unwrap_err();
        assert!(e.reason.contains("4294967295 triangles"), "{e}");
        assert!(parse_stl(b"so", "t.stl").is_err());
    }

    #[test]
    fn every_valid_ascii_variant_is_read() {
        let facet = "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";
        for text in [
            format!("solid\n{facet}endsolid\n"),
            format!("\n\n  solid t\n{facet}endsolid t\n"),
            format!(
                "solid {}\n{facet}endsolid\n",
                "a very long name ".repeat(20)
            ),
            format!("SOLID T\n{}ENDSOLID T\n", facet.to_uppercase()),
            format!("solid a\n{facet}endsolid a\nsolid b\n{facet}endsolid b\n"),
        ] {
            let (_, t) = parse_stl(text.as_bytes(), "a.stl").unwrap_or_else(|e| panic!("{e}"));
            assert!(!t.is_empty());
        }
        let e = parse_stl(b"solid\nfacet\nouter loop\nvertex 0 0\n", "a.stl").unwrap_err();
        assert_eq!(e.location.as_deref(), Some("line 4"), "{e}");
    }

    #[test]
    fn a_binary_file_whose_header_starts_with_solid_is_binary() {
        let mut header = b"solid exported by a tool".to_vec();
        header.resize(80, b' ');
        let mut b = header;
        b.extend_from_slice(&1u32.to_le_bytes());
        b.extend_from_slice(&[0u8; 50]);
        let (v, t) = parse_stl(&b, "t.stl").unwrap();
        assert_eq!((v.len(), t.len()), (3, 1));
    }

    #[test]
    fn ascii_is_read_and_truncation_is_an_error() {
        let text = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let (_, t) = parse_stl(text.as_bytes(), "a.stl").unwrap();
        assert_eq!(t.len(), 1);
        let cut = &text[..text.len() - 40];
        assert!(parse_stl(cut.as_bytes(), "a.stl").is_err());
    }
}
