//! Mutations: byte-level (flips, insertions, deletions, overwrites with boundary integers),
//! line- and token-level splicing between corpus files, and mutations that know what the input
//! is (numbers replaced by NaN, infinities, 1e308, -1; deep nesting; PNG checksums repaired so
//! a mutated image gets past the CRC check into the decoder).

use crate::rng::Rng;

/// What kind of input is mutated: picks the dictionary and the format-aware mutations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flavour {
    /// YAML scene text.
    Yaml,
    /// OBJ (and MTL) text.
    Obj,
    /// Binary image files (PNG, JPEG, PNM).
    Image,
    /// glTF's JSON (and GLB files, whose JSON chunk is text too).
    Json,
}

/// Numbers that break readers: non-finite values in every spelling, the extremes of f64 and
/// of the integer types, their neighbours, and forms some parsers take and others do not.
pub const INTERESTING_NUMBERS: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1",
    "2",
    "1e308",
    "-1e308",
    "1e400",
    "1e-308",
    "5e-324",
    ".nan",
    ".NaN",
    ".inf",
    "-.inf",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "infinity",
    "255",
    "256",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999999",
    "0x10",
    "1_000",
    "1.",
    ".5",
    "+3",
    "1e",
    "--1",
];

/// Tokens of the scene format, spliced in whole.
const YAML_TOKENS: &[&str] = &[
    "- add: ",
    "- define: ",
    "  extend: ",
    "  value: ",
    "camera",
    "light",
    "sphere",
    "plane",
    "cube",
    "cylinder",
    "cone",
    "group",
    "obj",
    "csg",
    "children:\n",
    "  children: []\n",
    "transform:\n",
    "    - [scale, 0, 0, 0]\n",
    "    - [translate, 1e308, 0, 0]\n",
    "    - [rotate-x, .nan]\n",
    "    - [shear, 1, 1, 1, 1, 1, 1]\n",
    "material:\n",
    "  pattern:\n",
    "type: perturbed\n",
    "type: map\n",
    "type: image\n",
    "mapping: cube\n",
    "colors: [[1, 1, 1], [0, 0, 0]]\n",
    "file: models/faceted-sphere.obj\n",
    "file: /dev/zero\n",
    "file: .\n",
    "file: nowhere.png\n",
    "width: ",
    "height: ",
    "field-of-view: ",
    "samples: ",
    "aperture: ",
    "focal-distance: ",
    "usteps: ",
    "vsteps: ",
    "corner: [0, 0, 0]\n",
    "angle: ",
    "operation: difference\n",
    "left: ",
    "right: ",
    "min: ",
    "max: ",
    "closed: true\n",
    "shadow: false\n",
    "refractive-index: ",
    "transparency: 1\n",
    "reflective: 1\n",
    ": ",
    "- ",
    "[",
    "]",
    "{",
    "}",
    ", ",
    "&a ",
    "*a",
    "<<: *a\n",
    "!!str ",
    "!!binary ",
    "? ",
    "|\n",
    ">-\n",
    "---\n",
    "...\n",
    "%YAML 1.2\n",
    "\t",
    "\n",
    "\r\n",
    "'",
    "\"",
    "\\u0000",
    "# ",
    "\u{feff}",
    "é",
    "\u{10ffff}",
];

/// Tokens of OBJ and MTL files.
const OBJ_TOKENS: &[&str] = &[
    "v ",
    "vn ",
    "vt ",
    "vp ",
    "f ",
    "g ",
    "o ",
    "s ",
    "l ",
    "usemtl ",
    "mtllib ",
    "newmtl ",
    "Kd ",
    "Ks ",
    "Ns ",
    "d ",
    "Tr ",
    "Ni ",
    "illum ",
    "map_Kd ",
    "/",
    "//",
    "-1",
    "0",
    " ",
    "\n",
    "\r\n",
    "\\\n",
    "#",
    "1/1/1 ",
    "-1/-1/-1 ",
    "2//2 ",
    "f 1 2 3\n",
    "v 0 0 0\n",
    "vn 0 0 0\n",
    "vt 0 0\n",
    "f 1 1 1\n",
    "f -1 -2 -3\n",
    "f 1/0/0 2/0/0 3/0/0\n",
];

/// Byte strings of the image formats (magic numbers, chunk names, markers).
/// glTF's keys and values that lead somewhere: references, counts, strides, URIs.
const JSON_TOKENS: &[&str] = &[
    "{",
    "}",
    "[",
    "]",
    ",",
    ":",
    "\"",
    "null",
    "-1",
    "0",
    "4294967295",
    "1e308",
    "\"POSITION\"",
    "\"NORMAL\"",
    "\"TANGENT\"",
    "\"TEXCOORD_0\"",
    "\"COLOR_0\"",
    "\"indices\"",
    "\"mode\"",
    "\"material\"",
    "\"accessors\"",
    "\"bufferView\"",
    "\"byteOffset\"",
    "\"byteLength\"",
    "\"byteStride\"",
    "\"count\"",
    "\"componentType\"",
    "5120",
    "5121",
    "5122",
    "5123",
    "5125",
    "5126",
    "\"type\"",
    "\"VEC3\"",
    "\"SCALAR\"",
    "\"sparse\"",
    "\"values\"",
    "\"buffers\"",
    "\"uri\"",
    "\"data:application/octet-stream;base64,AAAA\"",
    "\"../x.bin\"",
    "\"nodes\"",
    "\"children\"",
    "\"matrix\"",
    "\"rotation\"",
    "\"scale\"",
    "\"mesh\"",
    "\"camera\"",
    "\"cameras\"",
    "\"yfov\"",
    "\"xmag\"",
    "\"ymag\"",
    "\"textures\"",
    "\"images\"",
    "\"samplers\"",
    "\"wrapS\"",
    "33071",
    "33648",
    "10497",
    "\"alphaMode\"",
    "\"MASK\"",
    "\"BLEND\"",
    "\"extensionsRequired\"",
    "\"KHR_texture_transform\"",
    "\"KHR_lights_punctual\"",
];

const IMAGE_TOKENS: &[&[u8]] = &[
    b"\x89PNG\r\n\x1a\n",
    b"IHDR",
    b"IDAT",
    b"IEND",
    b"PLTE",
    b"tRNS",
    b"gAMA",
    b"iCCP",
    b"\xff\xd8\xff",
    b"\xff\xd9",
    b"\xff\xc0",
    b"\xff\xc2",
    b"\xff\xc4",
    b"\xff\xda",
    b"\xff\xdb",
    b"\xff\xdd",
    b"P1\n",
    b"P2\n",
    b"P3\n",
    b"P4\n",
    b"P5\n",
    b"P6\n",
    b"P7\n",
    b"WIDTH ",
    b"HEIGHT ",
    b"DEPTH ",
    b"MAXVAL ",
    b"TUPLTYPE RGB\n",
    b"ENDHDR\n",
    b"65535",
    b"4294967295",
    b"0 ",
    b"# comment\n",
];

/// Boundary integers written over binary fields.
const INTERESTING_INTS: &[u32] = &[
    0,
    1,
    2,
    0x7f,
    0x80,
    0xff,
    0x100,
    0x7fff,
    0x8000,
    0xffff,
    0x1_0000,
    0x4000,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_fffe,
    0xffff_ffff,
];

/// Mutates corpus inputs; deterministic for a seed.
pub struct Mutator {
    /// The random source.
    pub rng: Rng,
    flavour: Flavour,
    max_len: usize,
}

impl Mutator {
    /// A mutator of `flavour` inputs that never returns more than `max_len` bytes.
    pub fn new(seed: u64, flavour: Flavour, max_len: usize) -> Self {
        Self {
            rng: Rng::new(seed),
            flavour,
            max_len,
        }
    }

    /// A new input: a corpus entry with one to eight stacked mutations (other corpus entries
    /// supply splices).
    pub fn next_input(&mut self, corpus: &[Vec<u8>]) -> Vec<u8> {
        let mut data = self.rng.pick(corpus).clone();
        // Mostly one or two mutations, so that many inputs stay close enough to valid to get
        // deep into the reader; now and then a pile of them.
        let rounds = if self.rng.one_in(4) {
            1 + self.rng.below(8)
        } else {
            1 + self.rng.below(2)
        };
        for _ in 0..rounds {
            self.mutate(&mut data, corpus);
            data.truncate(self.max_len);
        }
        if self.flavour == Flavour::Image && !self.rng.one_in(5) {
            fix_png_checksums(&mut data);
        }
        data
    }

    /// Applies one random mutation to `data`.
    pub fn mutate(&mut self, data: &mut Vec<u8>, corpus: &[Vec<u8>]) {
        let text = self.flavour != Flavour::Image;
        let choice = self.rng.below(if text { 16 } else { 11 });
        match choice {
            0 => self.flip_bit(data),
            1 => self.set_byte(data),
            2 => self.delete_range(data),
            3 => self.duplicate_range(data),
            4 => self.insert_token(data),
            5 => self.overwrite_int(data),
            6 => self.splice_bytes(data, corpus),
            7 => self.insert_random_bytes(data),
            8 => self.truncate(data),
            9 => self.replace_number(data),
            10 => self.nest_deeply(data),
            11 => self.splice_lines(data, corpus),
            12 => self.crossover_lines(data, corpus),
            13 => self.shuffle_line(data),
            14 => self.repeat_line(data),
            _ => self.swap_tokens(data, corpus),
        }
    }

    fn flip_bit(&mut self, data: &mut [u8]) {
        if !data.is_empty() {
            let i = self.rng.below(data.len());
            data[i] ^= 1 << self.rng.below(8);
        }
    }

    fn set_byte(&mut self, data: &mut [u8]) {
        const BYTES: &[u8] = b"\x00\xff\x7f\x80\n\r\t -:[]{}&*!|>#'\"\\./0123456789";
        if !data.is_empty() {
            let i = self.rng.below(data.len());
            data[i] = if self.rng.one_in(2) {
                *self.rng.pick(BYTES)
            } else {
                self.rng.next_u64() as u8
            };
        }
    }

    /// A random range of `data`: start and length (at most `max`, at least 1 if not empty).
    fn range(&mut self, len: usize, max: usize) -> (usize, usize) {
        if len == 0 {
            return (0, 0);
        }
        let start = self.rng.below(len);
        let n = 1 + self.rng.below(max.min(len - start));
        (start, n)
    }

    fn delete_range(&mut self, data: &mut Vec<u8>) {
        let max = if self.rng.one_in(4) { 1024 } else { 16 };
        let (start, n) = self.range(data.len(), max);
        data.drain(start..start + n);
    }

    fn duplicate_range(&mut self, data: &mut Vec<u8>) {
        let (start, n) = self.range(data.len(), 256);
        let copy = data[start..start + n].to_vec();
        let at = self.rng.below(data.len() + 1);
        data.splice(at..at, copy);
    }

    fn insert_token(&mut self, data: &mut Vec<u8>) {
        let token: &[u8] = match self.flavour {
            Flavour::Yaml => self.rng.pick(YAML_TOKENS).as_bytes(),
            Flavour::Obj => self.rng.pick(OBJ_TOKENS).as_bytes(),
            Flavour::Image => IMAGE_TOKENS[self.rng.below(IMAGE_TOKENS.len())],
            Flavour::Json => self.rng.pick(JSON_TOKENS).as_bytes(),
        };
        // At a line start half the time, where statements begin.
        let at = if self.flavour != Flavour::Image && self.rng.one_in(2) {
            self.line_start(data)
        } else {
            self.rng.below(data.len() + 1)
        };
        data.splice(at..at, token.iter().copied());
    }

    fn insert_random_bytes(&mut self, data: &mut Vec<u8>) {
        let n = 1 + self.rng.below(32);
        let at = self.rng.below(data.len() + 1);
        let bytes: Vec<u8> = (0..n).map(|_| self.rng.next_u64() as u8).collect();
        data.splice(at..at, bytes);
    }

    fn truncate(&mut self, data: &mut Vec<u8>) {
        let at = self.rng.below(data.len() + 1);
        data.truncate(at);
    }

    /// Writes a boundary integer over 1, 2 or 4 bytes, big- or little-endian (sizes and
    /// lengths in image headers).
    fn overwrite_int(&mut self, data: &mut [u8]) {
        let v = *self.rng.pick(INTERESTING_INTS);
        let width = *self.rng.pick(&[1usize, 2, 4]);
        if data.len() < width {
            return;
        }
        let at = self.rng.below(data.len() - width + 1);
        let bytes = if self.rng.one_in(2) {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        let bytes = if self.rng.one_in(2) {
            &bytes[4 - width..]
        } else {
            &bytes[..width]
        };
        data[at..at + width].copy_from_slice(bytes);
    }

    /// Inserts a run of bytes from another corpus entry.
    fn splice_bytes(&mut self, data: &mut Vec<u8>, corpus: &[Vec<u8>]) {
        let other = self.rng.pick(corpus);
        let (start, n) = self.range(other.len(), 512);
        let at = self.rng.below(data.len() + 1);
        data.splice(at..at, other[start..start + n].iter().copied());
    }

    /// Replaces a number in the text (a run of digits, signs, points and exponents) with an
    /// interesting one; in binary data, writes one as text at a random place.
    fn replace_number(&mut self, data: &mut Vec<u8>) {
        let number = self.rng.pick(INTERESTING_NUMBERS).as_bytes();
        let spans = number_spans(data);
        if spans.is_empty() {
            let at = self.rng.below(data.len() + 1);
            data.splice(at..at, number.iter().copied());
            return;
        }
        let &(start, end) = self.rng.pick(&spans);
        data.splice(start..end, number.iter().copied());
    }

    /// Deep nesting: brackets around a span, nested groups or patterns, or a face with many
    /// corners; depths around and past the readers' limits.
    fn nest_deeply(&mut self, data: &mut Vec<u8>) {
        let depth = *self
            .rng
            .pick(&[8usize, 64, 99, 100, 101, 127, 128, 129, 300, 5000]);
        let at = self.line_start(data);
        let insert: Vec<u8> = match (self.flavour, self.rng.below(4)) {
            (Flavour::Obj, 0) => {
                let mut s = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf".to_vec();
                for i in 0..depth {
                    s.extend_from_slice(format!(" {}", i % 3 + 1).as_bytes());
                }
                s.push(b'\n');
                s
            }
            (Flavour::Obj, _) => {
                let mut s = Vec::new();
                for i in 0..depth.min(500) {
                    s.extend_from_slice(format!("g g{i}\nusemtl m{i}\nf -1 -2 -3\n").as_bytes());
                }
                s
            }
            (Flavour::Yaml, 0) => {
                let mut s = b"- add: group\n  children:\n".to_vec();
                let mut indent = String::from("    ");
                for _ in 0..depth.min(400) {
                    s.extend_from_slice(
                        format!("{indent}- add: group\n{indent}  children:\n").as_bytes(),
                    );
                    indent += "    ";
                }
                s.extend_from_slice(format!("{indent}- add: sphere\n").as_bytes());
                s
            }
            (Flavour::Yaml, 1) => {
                let mut pattern = String::from("{type: stripes, colors: [[1, 1, 1], [0, 0, 0]]}");
                for _ in 0..depth.min(400) {
                    pattern = format!("{{type: perturbed, pattern: {pattern}}}");
                }
                format!("- add: plane\n  material:\n    pattern: {pattern}\n").into_bytes()
            }
            (Flavour::Yaml, 2) => {
                let mut s = String::from("- define: d0\n  value: [[translate, 1, 0, 0]]\n");
                for i in 1..depth.min(64) {
                    s += &format!("- define: d{i}\n  value: [d{}, d{}]\n", i - 1, i - 1);
                }
                s += &format!("- add: sphere\n  transform: [d{}]\n", depth.min(64) - 1);
                s.into_bytes()
            }
            _ => {
                // Brackets around a random span.
                let (start, n) = self.range(data.len(), 64);
                let (open, close) = match self.rng.below(3) {
                    0 => ("[", "]"),
                    1 => ("{a: ", "}"),
                    _ => ("- ", ""),
                };
                let mut s = open.repeat(depth).into_bytes();
                s.extend_from_slice(&data[start..start + n]);
                s.extend_from_slice(close.repeat(depth).as_bytes());
                data.splice(start..start + n, s);
                return;
            }
        };
        data.splice(at..at, insert);
    }

    /// Copies one to three lines from another corpus entry to a line boundary here.
    fn splice_lines(&mut self, data: &mut Vec<u8>, corpus: &[Vec<u8>]) {
        let other: &Vec<u8> = self.rng.pick(corpus);
        let other = lines(other);
        if other.is_empty() {
            return;
        }
        let first = self.rng.below(other.len());
        let n = 1 + self.rng.below(3.min(other.len() - first));
        let chunk: Vec<u8> = other[first..first + n].concat();
        let at = self.line_start(data);
        data.splice(at..at, chunk);
    }

    /// This entry's lines up to a point, then another's from a point.
    fn crossover_lines(&mut self, data: &mut Vec<u8>, corpus: &[Vec<u8>]) {
        let mine = lines(data);
        let other: &Vec<u8> = self.rng.pick(corpus);
        let other = lines(other);
        let keep = self.rng.below(mine.len() + 1);
        let from = self.rng.below(other.len() + 1);
        let mut out: Vec<u8> = mine[..keep].concat();
        out.extend(other[from..].concat());
        *data = out;
    }

    /// Moves a line elsewhere.
    fn shuffle_line(&mut self, data: &mut Vec<u8>) {
        let mut ls: Vec<Vec<u8>> = lines(data).into_iter().map(<[u8]>::to_vec).collect();
        if ls.len() < 2 {
            return;
        }
        let line = ls.remove(self.rng.below(ls.len()));
        let to = self.rng.below(ls.len() + 1);
        ls.insert(to, line);
        *data = ls.concat();
    }

    /// Repeats a line many times (long lists, many objects, many warnings).
    fn repeat_line(&mut self, data: &mut Vec<u8>) {
        let ls = lines(data);
        if ls.is_empty() {
            return;
        }
        let i = self.rng.below(ls.len());
        let times = *self.rng.pick(&[2usize, 10, 150, 1000]);
        let line = ls[i].to_vec();
        let at: usize = ls[..i].iter().map(|l| l.len()).sum();
        let mut repeated = Vec::with_capacity(line.len() * times);
        for _ in 0..times {
            repeated.extend_from_slice(&line);
        }
        data.splice(at..at, repeated);
    }

    /// Replaces a word here with a word from another corpus entry (keys, names, values).
    fn swap_tokens(&mut self, data: &mut Vec<u8>, corpus: &[Vec<u8>]) {
        let mine = word_spans(data);
        let other_data = self.rng.pick(corpus);
        let theirs = word_spans(other_data);
        if mine.is_empty() || theirs.is_empty() {
            return;
        }
        let &(s, e) = self.rng.pick(&mine);
        let &(os, oe) = self.rng.pick(&theirs);
        let word = other_data[os..oe].to_vec();
        data.splice(s..e, word);
    }

    /// A random line boundary of `data`.
    fn line_start(&mut self, data: &[u8]) -> usize {
        let starts: Vec<usize> = std::iter::once(0)
            .chain(
                data.iter()
                    .enumerate()
                    .filter(|(_, &b)| b == b'\n')
                    .map(|(i, _)| i + 1),
            )
            .collect();
        *self.rng.pick(&starts)
    }
}

/// The lines of `data`, each with its line break.
pub fn lines(data: &[u8]) -> Vec<&[u8]> {
    data.split_inclusive(|&b| b == b'\n').collect()
}

/// Where the numbers in `data` are: runs of digits with signs, points and exponents.
fn number_spans(data: &[u8]) -> Vec<(usize, usize)> {
    let part = |b: u8| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E');
    let mut spans = Vec::new();
    let mut i = 0;
    while i < data.len() {
        if part(data[i]) {
            let start = i;
            while i < data.len() && part(data[i]) {
                i += 1;
            }
            if data[start..i].iter().any(u8::is_ascii_digit) {
                spans.push((start, i));
            }
        } else {
            i += 1;
        }
    }
    spans
}

/// Where the words of `data` are: runs of letters, digits, `-`, `_`, `.` and `/`.
fn word_spans(data: &[u8]) -> Vec<(usize, usize)> {
    let part = |b: u8| b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.' | b'/');
    let mut spans = Vec::new();
    let mut i = 0;
    while i < data.len() {
        if part(data[i]) {
            let start = i;
            while i < data.len() && part(data[i]) {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

/// Recomputes the CRC of every chunk of a PNG file in place (when the data starts with the PNG
/// signature), so mutated chunks reach the decoder instead of failing its checksum.
pub fn fix_png_checksums(data: &mut [u8]) {
    const SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";
    if !data.starts_with(SIGNATURE) {
        return;
    }
    let mut at = SIGNATURE.len();
    while at + 12 <= data.len() {
        let len = u32::from_be_bytes([data[at], data[at + 1], data[at + 2], data[at + 3]]) as usize;
        let Some(end) = (at + 8).checked_add(len) else {
            return;
        };
        if end + 4 > data.len() {
            return;
        }
        let crc = crc32fast::hash(&data[at + 4..end]);
        data[end..end + 4].copy_from_slice(&crc.to_be_bytes());
        at = end + 4;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_checksums_are_the_standard_crc32() {
        // An IEND chunk with a wrong CRC: PNG's own files end with AE 42 60 82.
        let mut data = b"\x89PNG\r\n\x1a\n\0\0\0\0IEND\0\0\0\0".to_vec();
        fix_png_checksums(&mut data);
        assert_eq!(data[data.len() - 4..], 0xAE42_6082u32.to_be_bytes());
        assert_eq!(crc32fast::hash(b"123456789"), 0xCBF4_3926);
    }

    #[test]
    fn numbers_are_found_and_replaced() {
        assert_eq!(number_spans(b"at: [1, -2.5e3, x]"), vec![(5, 6), (8, 14)]);
        let mut m = Mutator::new(1, Flavour::Yaml, 1 << 16);
        let mut data = b"width: 100\n".to_vec();
        m.replace_number(&mut data);
        assert!(data.starts_with(b"width: "));
        assert_ne!(data, b"width: 100\n");
    }

    #[test]
    fn mutations_are_deterministic_and_bounded() {
        let corpus = vec![b"- add: sphere\n  transform: [[scale, 1, 2, 3]]\n".to_vec()];
        let run = |seed| {
            let mut m = Mutator::new(seed, Flavour::Yaml, 4096);
            (0..200).map(|_| m.next_input(&corpus)).collect::<Vec<_>>()
        };
        let a = run(3);
        assert_eq!(a, run(3));
        assert_ne!(a, run(4));
        assert!(a.iter().all(|i| i.len() <= 4096));
    }
}
