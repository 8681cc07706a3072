//! VTK XML unstructured grids (`.vtu`) and a ParaView collection (`.pvd`), written and read by
//! hand: the format is small and the crates for it are unmaintained.
//!
//! A frame is binary: its arrays follow the XML header as raw little-endian bytes in one
//! `<AppendedData encoding="raw">` block (format 1.0, UInt64 byte counts), as the VTK XML
//! file format describes it. Raw rather than inline base64 (`format="binary"`): no encoding
//! pass, a third fewer bytes, and the f32 values on disk are the solver's own bits. The price
//! is a file that is XML only up to its appended block, which VTK and ParaView read but a
//! generic XML parser does not; [`read_vtu`] reads both it and the ASCII frames of earlier
//! runs.

use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// VTK cell types (vtkCellType.h).
const VTK_VERTEX: u8 = 1;
const VTK_TRIANGLE: u8 = 5;

/// One part of a frame: points (r, z) in the plane y = 0 (x = r, z = z), each a vertex cell
/// (the particles) or joined in triangles (the projectile's mesh), and named per-point and
/// per-cell scalar fields. What [`write_vtu`] writes and [`read_vtu`] gives back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Vtu {
    pub r: Vec<f32>,
    pub z: Vec<f32>,
    /// The cells: triangles of point indices, or `None` for one vertex cell per point.
    pub triangles: Option<Vec<[u32; 3]>>,
    pub point_data: Vec<(String, Vec<f32>)>,
    pub cell_data: Vec<(String, Vec<f32>)>,
}

impl Vtu {
    /// Cells: the triangles, or one vertex per point.
    pub fn cells(&self) -> usize {
        self.triangles.as_ref().map_or(self.r.len(), Vec::len)
    }

    /// The per-point field `name`.
    pub fn point_field(&self, name: &str) -> Option<&[f32]> {
        field(&self.point_data, name)
    }

    /// The per-cell field `name`.
    pub fn cell_field(&self, name: &str) -> Option<&[f32]> {
        field(&self.cell_data, name)
    }
}

fn field<'a>(fields: &'a [(String, Vec<f32>)], name: &str) -> Option<&'a [f32]> {
    fields
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, v)| v.as_slice())
}

/// Writes `grid` to `path` as a binary `.vtu`, whole or not at all ([`super::write_whole`]).
pub fn write_vtu(path: &Path, grid: &Vtu) -> io::Result<()> {
    let (n, cells) = (grid.r.len(), grid.cells());
    let points: Vec<f32> = grid
        .r
        .iter()
        .zip(&grid.z)
        .flat_map(|(&r, &z)| [r, 0.0, z])
        .collect();
    let (connectivity, offsets, types): (Vec<i32>, Vec<i32>, Vec<u8>) = match &grid.triangles {
        Some(t) => (
            t.iter().flatten().map(|&v| v as i32).collect(),
            (1..=cells as i32).map(|k| 3 * k).collect(),
            vec![VTK_TRIANGLE; cells],
        ),
        None => (
            (0..n as i32).collect(),
            (1..=n as i32).collect(),
            vec![VTK_VERTEX; n],
        ),
    };
    let mut out = Appended {
        xml: String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
             byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n",
        ),
        data: Vec::new(),
    };
    let _ = writeln!(
        out.xml,
        "<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{cells}\">\n<Points>"
    );
    out.array(None, 3, &points);
    out.xml.push_str("</Points>\n<Cells>\n");
    out.array(Some("connectivity"), 1, &connectivity);
    out.array(Some("offsets"), 1, &offsets);
    out.array(Some("types"), 1, &types);
    out.xml.push_str("</Cells>\n");
    for (tag, fields) in [
        ("PointData", &grid.point_data),
        ("CellData", &grid.cell_data),
    ] {
        let _ = writeln!(out.xml, "<{tag}>");
        for (name, values) in fields {
            out.array(Some(name), 1, values);
        }
        let _ = writeln!(out.xml, "</{tag}>");
    }
    out.xml
        .push_str("</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_");
    let mut bytes = out.xml.into_bytes();
    bytes.extend_from_slice(&out.data);
    bytes.extend_from_slice(b"\n</AppendedData>\n</VTKFile>\n");
    super::write_whole(path, &bytes)
}

/// A value of an appended array: its VTK type and its little-endian bytes.
trait Raw: Copy {
    const TYPE: &'static str;
    const SIZE: usize;
    fn extend(self, bytes: &mut Vec<u8>);
}

macro_rules! raw {
    ($($t:ty: $name:literal),*) => {$(
        impl Raw for $t {
            const TYPE: &'static str = $name;
            const SIZE: usize = std::mem::size_of::<$t>();
            fn extend(self, bytes: &mut Vec<u8>) {
                bytes.extend_from_slice(&self.to_le_bytes());
            }
        }
    )*};
}
raw!(f32: "Float32", i32: "Int32", u8: "UInt8");

/// A frame being written: its XML header, and the appended data its arrays point into.
struct Appended {
    xml: String,
    data: Vec<u8>,
}

impl Appended {
    /// Declares a `DataArray` of `values` and appends its byte count and bytes to the data, at
    /// the offset it declares.
    fn array<T: Raw>(&mut self, name: Option<&str>, components: usize, values: &[T]) {
        let name = name.map_or(String::new(), |n| format!(" Name=\"{}\"", escape(n)));
        let _ = writeln!(
            self.xml,
            "<DataArray type=\"{}\"{name} NumberOfComponents=\"{components}\" \
             format=\"appended\" offset=\"{}\"/>",
            T::TYPE,
            self.data.len()
        );
        let bytes = values.len() * T::SIZE;
        self.data.reserve(8 + bytes);
        self.data.extend_from_slice(&(bytes as u64).to_le_bytes());
        for &v in values {
            v.extend(&mut self.data);
        }
    }
}

/// `text` as an XML attribute value.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Reads a `.vtu` this code writes: binary (raw appended data, UInt32 or UInt64 byte counts)
/// or ASCII (the frames of earlier runs), of vertex or triangle cells and Float32 fields. A
/// file it cannot read is an error naming the file and what is wrong, never a panic.
pub fn read_vtu(path: &Path) -> Result<Vtu, String> {
    let bytes = super::run_files::read_run_file(path)?;
    parse(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// The kinds of array a frame holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Float32,
    Int32,
    UInt8,
}

impl Kind {
    fn named(name: &str) -> Result<Kind, String> {
        match name {
            "Float32" => Ok(Kind::Float32),
            "Int32" => Ok(Kind::Int32),
            "UInt8" => Ok(Kind::UInt8),
            _ => Err(format!(
                "DataArray type {name} is not read (Float32, Int32 and UInt8 are)"
            )),
        }
    }

    fn size(self) -> usize {
        match self {
            Kind::Float32 | Kind::Int32 => 4,
            Kind::UInt8 => 1,
        }
    }
}

/// An array's values, read by its kind; integers are kept as i64 until checked.
#[derive(Debug)]
enum Values {
    Float(Vec<f32>),
    Int(Vec<i64>),
}

/// A `DataArray` as declared: where it sits and what it holds.
struct Declared {
    section: String,
    name: Option<String>,
    kind: Kind,
    components: usize,
    /// The offset into the appended data, or the ASCII values in the element.
    source: Source,
}

enum Source {
    Appended(usize),
    Ascii(String),
}

/// One XML tag of the header: its name, attributes, whether it closes (`</x>`) or is empty
/// (`<x/>`), and the text after it up to the next tag.
struct Tag<'a> {
    name: &'a str,
    attributes: Vec<(&'a str, String)>,
    closing: bool,
    empty: bool,
    text: &'a str,
}

impl Tag<'_> {
    fn get(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| v.as_str())
    }

    fn require(&self, key: &str) -> Result<&str, String> {
        self.get(key)
            .ok_or_else(|| format!("<{}> has no {key} attribute", self.name))
    }
}

/// Splits XML text into tags, skipping the declaration and comments. `<AppendedData ...>` ends
/// the header: its byte offset after the tag comes back with the tags.
fn tags(xml: &str) -> Result<Vec<Tag<'_>>, String> {
    let mut out = Vec::new();
    let mut rest = xml;
    while let Some(open) = rest.find('<') {
        rest = &rest[open + 1..];
        if let Some(body) = rest.strip_prefix("!--") {
            let end = body.find("-->").ok_or("a comment does not end")?;
            rest = &body[end + 3..];
            continue;
        }
        let end = tag_end(rest).ok_or("a tag does not end")?;
        let (inside, after) = (&rest[..end], &rest[end + 1..]);
        rest = after;
        if inside.starts_with('?') {
            continue;
        }
        let text = &after[..after.find('<').unwrap_or(after.len())];
        let closing = inside.starts_with('/');
        let inside = inside.trim_start_matches('/');
        let empty = inside.ends_with('/');
        let inside = inside.trim_end_matches('/');
        let name_end = inside
            .find(|c: char| c.is_ascii_whitespace())
            .unwrap_or(inside.len());
        let name = &inside[..name_end];
        if name.is_empty() {
            return Err(format!("a tag without a name: <{inside}>"));
        }
        out.push(Tag {
            name,
            attributes: attributes(&inside[name_end..]).map_err(|e| format!("<{name}>: {e}"))?,
            closing,
            empty,
            text,
        });
    }
    Ok(out)
}

/// Where the tag that `text` starts in ends: its first `>` outside quotes.
fn tag_end(text: &str) -> Option<usize> {
    let mut quote = None;
    for (k, c) in text.char_indices() {
        match (quote, c) {
            (None, '>') => return Some(k),
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            _ => {}
        }
    }
    None
}

/// `key="value"` pairs (either quote), entities decoded.
fn attributes(mut text: &str) -> Result<Vec<(&str, String)>, String> {
    let mut out = Vec::new();
    loop {
        text = text.trim_start();
        if text.is_empty() {
            return Ok(out);
        }
        let eq = text
            .find('=')
            .ok_or_else(|| format!("`{text}` is not key=\"value\""))?;
        let key = text[..eq].trim_end();
        let value = text[eq + 1..].trim_start();
        let quote = value
            .chars()
            .next()
            .filter(|q| *q == '"' || *q == '\'')
            .ok_or_else(|| format!("the value of {key} is not quoted"))?;
        let end = value[1..]
            .find(quote)
            .ok_or_else(|| format!("the value of {key} does not end"))?;
        let raw = &value[1..1 + end];
        let decoded = raw
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&");
        out.push((key, decoded));
        text = &value[end + 2..];
    }
}

fn count(tag: &Tag, key: &str) -> Result<usize, String> {
    let text = tag.require(key)?;
    text.trim()
        .parse()
        .map_err(|_| format!("<{}> {key}=\"{text}\" is not a count", tag.name))
}

fn parse(bytes: &[u8]) -> Result<Vtu, String> {
    // The header is text up to the appended block, whose bytes are anything.
    let marker = b"<AppendedData";
    let header_end = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .unwrap_or(bytes.len());
    let header = std::str::from_utf8(&bytes[..header_end])
        .map_err(|e| format!("the XML header is not UTF-8 text ({e})"))?;
    let tags = tags(header)?;
    let file = tags
        .iter()
        .find(|t| !t.closing)
        .filter(|t| t.name == "VTKFile")
        .ok_or("not a VTK XML file: it does not start with <VTKFile>")?;
    if file.get("type") != Some("UnstructuredGrid") {
        return Err(format!(
            "a VTK file of type {}, not an UnstructuredGrid",
            file.get("type").unwrap_or("(none)")
        ));
    }
    if let Some(order) = file.get("byte_order").filter(|o| *o != "LittleEndian") {
        return Err(format!("byte_order {order} is not read (LittleEndian is)"));
    }
    if let Some(c) = file.get("compressor") {
        return Err(format!("compressed data ({c}) is not read"));
    }
    let header_bytes = match file.get("header_type").unwrap_or("UInt32") {
        "UInt32" => 4,
        "UInt64" => 8,
        other => return Err(format!("header_type {other} is not UInt32 or UInt64")),
    };
    let pieces: Vec<&Tag> = tags
        .iter()
        .filter(|t| t.name == "Piece" && !t.closing)
        .collect();
    let [piece] = pieces[..] else {
        return Err(format!("{} pieces; one is read", pieces.len()));
    };
    let (points, cells) = (
        count(piece, "NumberOfPoints")?,
        count(piece, "NumberOfCells")?,
    );
    let arrays = declared(&tags)?;
    let appended = if header_end < bytes.len() {
        Some(appended_data(&bytes[header_end..]).map(|start| &bytes[header_end + start..])?)
    } else {
        None
    };
    let read = |a: &Declared, expected: usize| -> Result<Values, String> {
        let what = describe(a);
        let expected = expected
            .checked_mul(a.components)
            .ok_or_else(|| format!("{what}: too many values to read"))?;
        let values = match &a.source {
            Source::Ascii(text) => ascii(text, a.kind),
            Source::Appended(offset) => {
                let data = appended.ok_or("no <AppendedData> block for the appended arrays")?;
                binary(data, *offset, header_bytes, a.kind)
            }
        }
        .map_err(|e| format!("{what}: {e}"))?;
        let len = match &values {
            Values::Float(v) => v.len(),
            Values::Int(v) => v.len(),
        };
        if len != expected {
            return Err(format!("{what} holds {len} values, not {expected}"));
        }
        Ok(values)
    };
    let find = |section: &str, name: Option<&str>| {
        arrays
            .iter()
            .find(|a| a.section == section && (name.is_none() || a.name.as_deref() == name))
            .ok_or_else(|| match name {
                Some(n) => format!("no {n} array in <{section}>"),
                None => format!("no array in <{section}>"),
            })
    };
    let point_array = find("Points", None)?;
    if point_array.components != 3 || point_array.kind != Kind::Float32 {
        return Err("the points are not Float32 in threes".into());
    }
    let Values::Float(xyz) = read(point_array, points)? else {
        unreachable!("a Float32 array reads as floats")
    };
    let integers = |name: &str, kind: Kind, expected: usize| -> Result<Vec<i64>, String> {
        let a = find("Cells", Some(name))?;
        if a.kind != kind || a.components != 1 {
            return Err(format!("{} is not {kind:?}", describe(a)));
        }
        match read(a, expected)? {
            Values::Int(v) => Ok(v),
            Values::Float(_) => unreachable!("an integer array reads as integers"),
        }
    };
    let offsets = integers("offsets", Kind::Int32, cells)?;
    let types = integers("types", Kind::UInt8, cells)?;
    let size = offsets.last().copied().unwrap_or(0).max(0) as usize;
    let connectivity = integers("connectivity", Kind::Int32, size)?;
    let triangles = cell_points(&connectivity, &offsets, &types, points)?;
    let fields = |section: &str, expected: usize| -> Result<Vec<(String, Vec<f32>)>, String> {
        arrays
            .iter()
            .filter(|a| a.section == section)
            .map(|a| {
                let name = a.name.clone().ok_or("an array without a Name")?;
                if a.kind != Kind::Float32 || a.components != 1 {
                    return Err(format!("{} is not a Float32 scalar", describe(a)));
                }
                match read(a, expected)? {
                    Values::Float(v) => Ok((name, v)),
                    Values::Int(_) => unreachable!("a Float32 array reads as floats"),
                }
            })
            .collect()
    };
    Ok(Vtu {
        r: xyz.chunks_exact(3).map(|p| p[0]).collect(),
        z: xyz.chunks_exact(3).map(|p| p[2]).collect(),
        triangles,
        point_data: fields("PointData", points)?,
        cell_data: fields("CellData", cells)?,
    })
}

fn describe(a: &Declared) -> String {
    match &a.name {
        Some(n) => format!("<{}> array {n}", a.section),
        None => format!("<{}> array", a.section),
    }
}

/// The `DataArray`s of the header, each with the section it is in.
fn declared(tags: &[Tag]) -> Result<Vec<Declared>, String> {
    let mut section = String::new();
    let mut out = Vec::new();
    for tag in tags {
        match tag.name {
            "Points" | "Cells" | "PointData" | "CellData" if !tag.closing => {
                section = tag.name.to_string();
            }
            "DataArray" if !tag.closing => {
                let kind = Kind::named(tag.require("type")?)?;
                let components = match tag.get("NumberOfComponents") {
                    Some(_) => count(tag, "NumberOfComponents")?,
                    None => 1,
                };
                let source = match tag.get("format").unwrap_or("") {
                    "appended" => Source::Appended(count(tag, "offset")?),
                    "ascii" if !tag.empty => Source::Ascii(tag.text.to_string()),
                    "ascii" => Source::Ascii(String::new()),
                    other => {
                        return Err(format!(
                            "DataArray format \"{other}\" is not read (appended and ascii are)"
                        ))
                    }
                };
                out.push(Declared {
                    section: section.clone(),
                    name: tag.get("Name").map(str::to_string),
                    kind,
                    components,
                    source,
                });
            }
            _ => {}
        }
    }
    Ok(out)
}

/// Where the raw bytes start in `block` (from `<AppendedData` on): after the `_` that follows
/// the tag.
fn appended_data(block: &[u8]) -> Result<usize, String> {
    let end = block
        .iter()
        .position(|&b| b == b'>')
        .ok_or("<AppendedData> does not end")?;
    let tag = std::str::from_utf8(&block[..=end]).map_err(|_| "<AppendedData> is not text")?;
    let encoding = tags(tag)?
        .first()
        .and_then(|t| t.get("encoding").map(str::to_string));
    if encoding.as_deref() != Some("raw") {
        return Err(format!(
            "appended data encoded as {}, not raw",
            encoding.as_deref().unwrap_or("(unsaid)")
        ));
    }
    let underscore = block[end + 1..]
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .map(|k| end + 1 + k)
        .filter(|&k| block[k] == b'_')
        .ok_or("the appended data does not start with `_`")?;
    Ok(underscore + 1)
}

/// The values of an appended array at `offset` in `data`: a byte count of `header` bytes, then
/// the bytes.
fn binary(data: &[u8], offset: usize, header: usize, kind: Kind) -> Result<Values, String> {
    let short = || format!("its data at offset {offset} run past the end of the file");
    let start = offset.checked_add(header).ok_or_else(short)?;
    let head = data.get(offset..start).ok_or_else(short)?;
    let mut le = [0; 8];
    le[..header].copy_from_slice(head);
    let len = usize::try_from(u64::from_le_bytes(le)).map_err(|_| short())?;
    let bytes = data
        .get(start..start.checked_add(len).ok_or_else(short)?)
        .ok_or_else(short)?;
    if len % kind.size() != 0 {
        return Err(format!("{len} bytes are not whole {kind:?} values"));
    }
    Ok(match kind {
        Kind::Float32 => Values::Float(
            bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect(),
        ),
        Kind::Int32 => Values::Int(
            bytes
                .chunks_exact(4)
                .map(|b| i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as i64)
                .collect(),
        ),
        Kind::UInt8 => Values::Int(bytes.iter().map(|&b| b as i64).collect()),
    })
}

/// The values of an ASCII array.
fn ascii(text: &str, kind: Kind) -> Result<Values, String> {
    let words = text.split_whitespace();
    let bad = |w: &str| format!("`{w}` is not a {kind:?} value");
    Ok(match kind {
        Kind::Float32 => Values::Float(
            words
                .map(|w| w.parse::<f32>().map_err(|_| bad(w)))
                .collect::<Result<_, _>>()?,
        ),
        Kind::Int32 | Kind::UInt8 => {
            let range = if kind == Kind::UInt8 {
                0..=u8::MAX as i64
            } else {
                i32::MIN as i64..=i32::MAX as i64
            };
            Values::Int(
                words
                    .map(|w| {
                        w.parse::<i64>()
                            .ok()
                            .filter(|v| range.contains(v))
                            .ok_or_else(|| bad(w))
                    })
                    .collect::<Result<_, _>>()?,
            )
        }
    })
}

/// The triangles of the cells, or `None` where every cell is the vertex of its own point (in
/// order, as [`write_vtu`] writes particles); any other cells are an error.
fn cell_points(
    connectivity: &[i64],
    offsets: &[i64],
    types: &[i64],
    points: usize,
) -> Result<Option<Vec<[u32; 3]>>, String> {
    let mut start = 0;
    let mut triangles = Vec::new();
    let mut vertices = 0;
    for (k, (&end, &kind)) in offsets.iter().zip(types).enumerate() {
        let end = usize::try_from(end)
            .ok()
            .filter(|&e| e >= start && e <= connectivity.len())
            .ok_or_else(|| format!("cell {k}'s offset {end} is out of order"))?;
        let corners = &connectivity[start..end];
        start = end;
        let index = |&v: &i64| {
            usize::try_from(v)
                .ok()
                .filter(|&v| v < points)
                .map(|v| v as u32)
                .ok_or_else(|| format!("cell {k} names point {v} of {points}"))
        };
        match (kind as u8, corners) {
            (VTK_TRIANGLE, [a, b, c]) => triangles.push([index(a)?, index(b)?, index(c)?]),
            (VTK_VERTEX, [v]) if index(v)? as usize == k => vertices += 1,
            (VTK_VERTEX, [_]) => {
                return Err(format!("vertex cell {k} is not of point {k}"));
            }
            _ => {
                return Err(format!(
                    "cell {k} is of VTK type {kind} with {} points; only vertices (1) and \
                     triangles (5) are read",
                    corners.len()
                ))
            }
        }
    }
    match (vertices, triangles.len()) {
        (0, _) if !offsets.is_empty() => Ok(Some(triangles)),
        (v, 0) if v == points => Ok(None),
        (_, 0) => Err(format!("{vertices} vertex cells for {points} points")),
        _ => Err("vertex and triangle cells mixed".into()),
    }
}

/// One file a `.pvd` collection lists: the time it shows (s), its part, and its path
/// relative to the collection.
#[derive(Clone, Debug, PartialEq)]
pub struct DataSet {
    pub time: f64,
    pub part: usize,
    pub file: String,
}

/// The files a `.pvd` collection ([`Collection`]) lists, in its order; an error naming the
/// file and what is wrong with it.
pub fn read_pvd(path: &Path) -> Result<Vec<DataSet>, String> {
    let fail = |why: String| format!("{}: {why}", path.display());
    let bytes = super::run_files::read_run_file(path)?;
    let text = std::str::from_utf8(&bytes).map_err(|_| fail("not UTF-8 text".into()))?;
    let tags = tags(text).map_err(fail)?;
    if !tags
        .iter()
        .find(|t| !t.closing)
        .is_some_and(|t| t.name == "VTKFile" && t.get("type") == Some("Collection"))
    {
        return Err(fail(
            "not a VTK collection: it does not start with <VTKFile type=\"Collection\">".into(),
        ));
    }
    tags.iter()
        .filter(|t| t.name == "DataSet" && !t.closing)
        .map(|t| {
            let time = t.require("timestep")?;
            let time = time
                .trim()
                .parse::<f64>()
                .map_err(|_| format!("<DataSet> timestep=\"{time}\" is not a number"))?;
            let part = match t.get("part") {
                Some(_) => count(t, "part")?,
                None => 0,
            };
            let file = t.require("file")?.to_string();
            Ok(DataSet { time, part, file })
        })
        .collect::<Result<_, String>>()
        .map_err(fail)
}

/// A `.pvd` collection: one entry per frame and part, rewritten whole after every frame so that
/// a run that stops early, or cannot write, still leaves a readable collection.
#[derive(Debug, Default)]
pub struct Collection {
    path: PathBuf,
    entries: Vec<(f64, usize, String)>,
}

impl Collection {
    pub fn new(path: PathBuf) -> Collection {
        Collection {
            path,
            entries: Vec::new(),
        }
    }

    /// A restarted run's collection: the `entries` its checkpoint kept, written out at once,
    /// so that frames a killed run wrote after the checkpoint are no longer listed.
    pub fn resume(path: PathBuf, entries: Vec<(f64, usize, String)>) -> io::Result<Collection> {
        let pvd = Collection { path, entries };
        pvd.write()?;
        Ok(pvd)
    }

    /// The entries so far: time (s), part (0 the target, 1 the projectile) and file name.
    pub fn entries(&self) -> &[(f64, usize, String)] {
        &self.entries
    }

    pub fn add(&mut self, time: f64, part: usize, file: &str) -> io::Result<()> {
        self.entries.push((time, part, file.to_string()));
        self.write()
    }

    fn write(&self) -> io::Result<()> {
        let mut s = String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n");
        for (t, p, f) in &self.entries {
            let _ = writeln!(s, "<DataSet timestep=\"{t:e}\" part=\"{p}\" file=\"{f}\"/>");
        }
        s.push_str("</Collection>\n</VTKFile>\n");
        super::write_whole(&self.path, s.as_bytes())
    }
}

#[cfg(test)]
mod tests;
