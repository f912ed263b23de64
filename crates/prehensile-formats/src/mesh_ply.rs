//! PLY (ascii, binary little- and big-endian): the `vertex` element's x, y, z and the `face`
//! element's vertex index list; other elements and properties are skipped.
//!
//! Written by hand: the one PLY crate (`ply-rs`) has been unmaintained since 2018, and we need
//! bounded allocation on absurd element counts and errors that name the element and line.

use prehensile_core::math::Point3;

use crate::FormatError;

#[derive(Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

#[derive(Debug, Clone, Copy)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Reads values one at a time from the body, ascii or binary.
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    encoding: Encoding,
    line: usize,
    source: &'a str,
}

impl Body<'_> {
    fn err(&self, what: &str) -> FormatError {
        let at = match self.encoding {
            Encoding::Ascii => format!("line {}", self.line),
            _ => format!("byte {}", self.pos),
        };
        FormatError::at(self.source, at, what.to_string())
    }

    fn read(&mut self, s: Scalar) -> Result<f64, FormatError> {
        if self.encoding == Encoding::Ascii {
            while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
                if self.bytes[self.pos] == b'\n' {
                    self.line += 1;
                }
                self.pos += 1;
            }
            let start = self.pos;
            while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            if start == self.pos {
                return Err(self.err("the file ends before all elements declared in the header"));
            }
            let word = std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("?");
            // Integer properties are read as integers: "0.9" or "nan" as an index is an error,
            // not vertex 0.
            if !matches!(s, Scalar::F32 | Scalar::F64) {
                return word.parse::<i64>().map(|v| v as f64).map_err(|_| {
                    self.err(&format!("'{word}' is not a whole number ({s:?} property)"))
                });
            }
            return word
                .parse()
                .map_err(|_| self.err(&format!("'{word}' is not a number")));
        }
        let n = s.size();
        let Some(raw) = self.bytes.get(self.pos..self.pos + n) else {
            return Err(
                self.err("the file ends before all elements declared in the header (truncated)")
            );
        };
        self.pos += n;
        let mut buf = [0u8; 8];
        buf[..n].copy_from_slice(raw);
        if self.encoding == Encoding::Big {
            buf[..n].reverse();
        }
        Ok(match s {
            Scalar::I8 => buf[0] as i8 as f64,
            Scalar::U8 => buf[0] as f64,
            Scalar::I16 => i16::from_le_bytes([buf[0], buf[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([buf[0], buf[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(buf),
        })
    }
}

/// Parses PLY bytes into positions and triangles (polygons are fanned).
pub fn parse_ply(
    bytes: &[u8],
    source_name: &str,
) -> Result<(Vec<Point3>, Vec<[usize; 3]>), FormatError> {
    let header_end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .ok_or_else(|| {
            FormatError::new(source_name, "no 'end_header' line; this is not a PLY file")
        })?;
    let header = std::str::from_utf8(&bytes[..header_end])
        .map_err(|_| FormatError::at(source_name, "header", "the header is not text"))?;
    let (encoding, elements) = parse_header(header, source_name)?;
    let mut body_start = header_end + "end_header".len();
    while body_start < bytes.len() && bytes[body_start] != b'\n' {
        body_start += 1;
    }
    body_start += 1;
    let body_len = bytes.len().saturating_sub(body_start);
    let mut body = Body {
        bytes: &bytes[body_start.min(bytes.len())..],
        pos: 0,
        encoding,
        line: header.lines().count() + 2,
        source: source_name,
    };
    let mut mesh = (Vec::new(), Vec::new());
    for e in &elements {
        // Each element needs at least one byte (binary) or two characters (ascii): bound the
        // allocation by the file size before trusting the header's count.
        if e.count > body_len {
            return Err(FormatError::at(
                source_name,
                format!("element '{}'", e.name),
                format!(
                    "the header declares {} of them but the body has only {body_len} bytes",
                    e.count
                ),
            ));
        }
        read_element(e, &mut body, &mut mesh)?;
    }
    if mesh.1.is_empty() {
        return Err(FormatError::new(source_name, "the PLY has no faces"));
    }
    Ok(mesh)
}

/// The header's encoding and elements (the text before `end_header`).
fn parse_header(header: &str, source_name: &str) -> Result<(Encoding, Vec<Element>), FormatError> {
    let mut lines = header.lines().enumerate();
    if lines.next().map(|(_, l)| l.trim()) != Some("ply") {
        return Err(FormatError::at(
            source_name,
            "line 1",
            "a PLY file starts with 'ply'",
        ));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for (n, line) in lines {
        let err = |reason: String| FormatError::at(source_name, format!("line {}", n + 1), reason);
        let w: Vec<&str> = line.split_whitespace().collect();
        let property = |elements: &mut Vec<Element>, p: Property| {
            let e = elements
                .last_mut()
                .ok_or_else(|| err("property before any element".into()))?;
            e.properties.push(p);
            Ok::<_, FormatError>(())
        };
        match w.as_slice() {
            ["format", f, _] => {
                encoding = Some(match *f {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    other => return Err(err(format!("unknown format '{other}'"))),
                })
            }
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| err(format!("'{count}' is not a count")))?,
                properties: Vec::new(),
            }),
            ["property", "list", c, t, name] => {
                let (Some(c), Some(t)) = (Scalar::parse(c), Scalar::parse(t)) else {
                    return Err(err("unknown property type".into()));
                };
                property(&mut elements, Property::List(name.to_string(), c, t))?;
            }
            ["property", t, name] => {
                let t =
                    Scalar::parse(t).ok_or_else(|| err(format!("unknown property type '{t}'")))?;
                property(&mut elements, Property::Scalar(name.to_string(), t))?;
            }
            _ => {}
        }
    }
    let encoding =
        encoding.ok_or_else(|| FormatError::at(source_name, "header", "no 'format' line"))?;
    Ok((encoding, elements))
}

/// Reads every instance of element `e`, adding vertices and faces (fanned) to `mesh`; other
/// elements are read past.
fn read_element(
    e: &Element,
    body: &mut Body,
    (vertices, triangles): &mut (Vec<Point3>, Vec<[usize; 3]>),
) -> Result<(), FormatError> {
    let xyz: Vec<Option<usize>> = ["x", "y", "z"]
        .iter()
        .map(|n| {
            e.properties
                .iter()
                .position(|p| matches!(p, Property::Scalar(s, _) if s == n))
        })
        .collect();
    if e.name == "vertex" && xyz.iter().any(Option::is_none) {
        return Err(FormatError::at(
            body.source,
            "element 'vertex'",
            "it has no x, y and z properties",
        ));
    }
    for _ in 0..e.count {
        let (p, face) = read_instance(e, body, &xyz)?;
        if e.name == "vertex" {
            vertices.push(Point3::from(p));
        } else if e.name == "face" {
            if face.len() < 3 {
                return Err(body.err(&format!(
                    "face {} has fewer than 3 vertices",
                    triangles.len()
                )));
            }
            let idx: Vec<usize> = face
                .iter()
                .map(|&v| {
                    if !(v >= 0.0 && v < vertices.len() as f64 && v.fract() == 0.0) {
                        Err(body.err(&format!(
                            "face refers to vertex {v}, but there are {} vertices",
                            vertices.len()
                        )))
                    } else {
                        Ok(v as usize)
                    }
                })
                .collect::<Result<_, _>>()?;
            for k in 1..idx.len() - 1 {
                triangles.push([idx[0], idx[k], idx[k + 1]]);
            }
        }
    }
    Ok(())
}

/// One instance of element `e`: its x, y, z (where `xyz` says they are) and a face's vertex
/// indices.
fn read_instance(
    e: &Element,
    body: &mut Body,
    xyz: &[Option<usize>],
) -> Result<([f64; 3], Vec<f64>), FormatError> {
    let mut p = [0.0; 3];
    let mut face = Vec::new();
    for (k, prop) in e.properties.iter().enumerate() {
        match prop {
            Property::Scalar(_, t) => {
                let v = body.read(*t)?;
                if let Some(axis) = xyz.iter().position(|&i| i == Some(k)) {
                    p[axis] = v;
                }
            }
            Property::List(name, c, t) => {
                let len = body.read(*c)?;
                if !(0.0..=1024.0).contains(&len) || len.fract() != 0.0 {
                    return Err(body.err(&format!("a list of {len} entries is not plausible")));
                }
                let keep = e.name == "face" && (name == "vertex_indices" || name == "vertex_index");
                for _ in 0..len as usize {
                    let v = body.read(*t)?;
                    if keep {
                        face.push(v);
                    }
                }
            }
        }
    }
    Ok((p, face))
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

    #[test]
    fn fractional_or_nan_indices_are_errors_not_vertex_zero() {
        for bad in ["3 0.9 1 2", "3 nan 1 2", "3 0 1 2.5", "2.5 0 1 2"] {
            let text = ASCII.replace("3 0 1 2", bad);
            let e = parse_ply(text.as_bytes(), "bad.ply").unwrap_err();
            assert!(e.reason.contains("whole number"), "{bad}: {e}");
        }
        // Float index lists (allowed by the format) must still hold whole numbers.
        let text = ASCII
            .replace("list uchar int", "list uchar float")
            .replace("3 0 1 2", "3 0 1 2.5");
        assert!(parse_ply(text.as_bytes(), "f.ply").is_err());
    }

    #[test]
    fn ascii_and_binary_agree() {
        let (v, t) = parse_ply(ASCII.as_bytes(), "a.ply").unwrap();
        assert_eq!((v.len(), t.len()), (3, 1));
        let mut bin = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
        for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
            for c in p {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        bin.push(3);
        for i in [0i32, 1, 2] {
            bin.extend_from_slice(&i.to_le_bytes());
        }
        let (v2, t2) = parse_ply(&bin, "b.ply").unwrap();
        assert_eq!(v, v2);
        assert_eq!(t, t2);
        let e = parse_ply(&bin[..bin.len() - 3], "b.ply").unwrap_err();
        assert!(e.reason.contains("truncated"), "{e}");
    }

    #[test]
    fn bad_counts_and_indices_are_errors() {
        let huge = ASCII.replace("element vertex 3", "element vertex 999999999999");
        assert!(parse_ply(huge.as_bytes(), "h.ply")
            .unwrap_err()
            .reason
            .contains("declares"));
        let bad = ASCII.replace("3 0 1 2", "3 0 1 9");
        let e = parse_ply(bad.as_bytes(), "i.ply").unwrap_err();
        assert!(e.reason.contains("vertex 9"), "{e}");
        assert_eq!(e.location.as_deref(), Some("line 13"));
    }
}
