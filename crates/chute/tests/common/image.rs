//! Reading PNGs back for tests that look at pixels (plots, viewer screenshots).

use std::path::Path;

/// An RGB image.
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[u8; 3]>,
}

impl Image {
    /// Decode an 8-bit RGB or RGBA PNG (alpha dropped).
    pub fn read(path: &Path) -> Image {
        let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut reader = png::Decoder::new(file).read_info().expect("a PNG");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("PNG data");
        assert_eq!(info.bit_depth, png::BitDepth::Eight, "{}", path.display());
        let channels = match info.color_type {
            png::ColorType::Rgb => 3,
            png::ColorType::Rgba => 4,
            other => panic!("{}: unexpected colour type {other:?}", path.display()),
        };
        let pixels = buf[..info.buffer_size()]
            .chunks_exact(channels)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        Image {
            width: info.width,
            height: info.height,
            pixels,
        }
    }

    pub fn at(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[(y * self.width + x) as usize]
    }

    /// The pixels of the rectangle [x0, x1) × [y0, y1), clamped to the image.
    pub fn region(&self, (x0, y0, x1, y1): (u32, u32, u32, u32)) -> Vec<[u8; 3]> {
        let (x1, y1) = (x1.min(self.width), y1.min(self.height));
        let mut out = Vec::new();
        for y in y0..y1 {
            for x in x0..x1 {
                out.push(self.at(x, y));
            }
        }
        out
    }
}

/// Largest channel difference of two pixels.
pub fn distance(a: [u8; 3], b: [u8; 3]) -> u8 {
    (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap()
}

/// Fraction of `pixels` for which `pred` holds.
pub fn fraction(pixels: &[[u8; 3]], pred: impl Fn([u8; 3]) -> bool) -> f64 {
    pixels.iter().filter(|&&p| pred(p)).count() as f64 / pixels.len().max(1) as f64
}

/// Whether a pixel is coloured (not white, grey or black): the spread of its channels.
pub fn saturated(p: [u8; 3], min_spread: u8) -> bool {
    p.iter().max().unwrap() - p.iter().min().unwrap() >= min_spread
}
