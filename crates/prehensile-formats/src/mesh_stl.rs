//! STL, ascii and binary, read with the `stl_io` crate after our own size checks (a binary
//! header's triangle count is checked against the file length before anything is allocated).

use std::io::Cursor;

use prehensile_core::math::Point3;

use crate::FormatError;

/// Parses STL bytes into positions and triangles.
pub fn parse_stl(
    bytes: &[u8],
    source_name: &str,
) -> Result<(Vec<Point3>, Vec<[usize; 3]>), FormatError> {
    let looks_ascii = bytes.trim_ascii_start().starts_with(b"solid")
        && bytes.windows(5).take(1000).any(|w| w == b"facet");
    if !looks_ascii {
        if bytes.len() < 84 {
            return Err(FormatError::new(
                source_name,
                format!("{} bytes is too short for a binary STL (header alone is 84 bytes); the file is truncated", bytes.len()),
            ));
        }
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        let expected = 84 + 50 * count;
        if bytes.len() as u64 != expected {
            return Err(FormatError::at(
                source_name,
                "header",
                format!(
                    "the header declares {count} triangles ({expected} bytes) but the file has {} bytes; the file is truncated or not an STL",
                    bytes.len()
                ),
            ));
        }
    }
    let mesh = stl_io::read_stl(&mut Cursor::new(bytes))
        .map_err(|e| FormatError::new(source_name, format!("not a valid STL: {e}")))?;
    let vertices = mesh
        .vertices
        .iter()
        .map(|v| Point3::new(v[0] as f64, v[1] as f64, v[2] as f64))
        .collect();
    let triangles: Vec<[usize; 3]> = mesh.faces.iter().map(|f| f.vertices).collect();
    if triangles.is_empty() {
        return Err(FormatError::new(source_name, "the STL has no triangles"));
    }
    Ok((vertices, triangles))
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
    fn ascii_is_read_and_truncation_is_an_error() {
        let text = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let (_, t) = parse_stl(text.as_bytes(), "a.stl").unwrap();
        assert_eq!(t.len(), 1);
        let cut = &text[..text.len() - 40];
        assert!(parse_stl(cut.as_bytes(), "a.stl").is_err());
    }
}
