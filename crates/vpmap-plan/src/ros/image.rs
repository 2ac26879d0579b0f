//! Decoding a `map_server` map's image: PGM (`P2`, `P5`) and PNG, to grey levels.

use std::path::Path;

use crate::error::{PlanError, Result};
use crate::grid::{MAX_CELLS, checked_cell_count};

/// A decoded greyscale image, rows from the top.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct GreyImage {
    pub(super) width: usize,
    pub(super) height: usize,
    /// Largest possible sample value (PGM maxval; 255 for PNG).
    pub(super) max_value: u8,
    pub(super) grey: Vec<u8>,
    /// Alpha per pixel, when the image has an alpha channel.
    pub(super) alpha: Option<Vec<u8>>,
}

/// A cursor over a PGM header.
struct PgmHeader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl PgmHeader<'_> {
    /// Skip whitespace and `#` comments.
    fn skip_space(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            if b == b'#' {
                while self
                    .bytes
                    .get(self.pos)
                    .is_some_and(|&c| c != b'\n' && c != b'\r')
                {
                    self.pos += 1;
                }
            } else if b.is_ascii_whitespace() {
                self.pos += 1;
            } else {
                break;
            }
        }
    }

    /// The next unsigned decimal number, or `None` when the next token is not one.
    fn number(&mut self) -> Option<u64> {
        self.skip_space();
        let start = self.pos;
        let mut value: u64 = 0;
        while let Some(&b) = self.bytes.get(self.pos) {
            if !b.is_ascii_digit() {
                break;
            }
            value = value.saturating_mul(10).saturating_add(u64::from(b - b'0'));
            self.pos += 1;
        }
        (self.pos > start).then_some(value)
    }
}

pub(super) fn decode_pgm(bytes: &[u8], path: &Path) -> Result<GreyImage> {
    let malformed = |reason: String| PlanError::MalformedImage {
        path: path.to_path_buf(),
        reason,
    };
    let ascii = match bytes.get(..2) {
        Some(b"P5") => false,
        Some(b"P2") => true,
        _ => return Err(malformed("not a PGM file (no P2 or P5 magic)".to_owned())),
    };
    let mut header = PgmHeader { bytes, pos: 2 };
    let mut field = |name: &str| {
        header
            .number()
            .ok_or_else(|| malformed(format!("the header has no {name}")))
    };
    let width = field("width")?;
    let height = field("height")?;
    let maxval = field("maxval")?;
    let width = usize::try_from(width).unwrap_or(usize::MAX);
    let height = usize::try_from(height).unwrap_or(usize::MAX);
    let n = checked_cell_count(width, height)?;
    let max_value = match u8::try_from(maxval) {
        Ok(0) => return Err(malformed("maxval is 0".to_owned())),
        Ok(m) => m,
        Err(_) => {
            return Err(PlanError::UnsupportedImage {
                path: path.to_path_buf(),
                reason: format!("PGM maxval {maxval} (16-bit samples); maxval must be at most 255"),
            });
        }
    };
    let grey = if ascii {
        let mut grey = Vec::with_capacity(n);
        for i in 0..n {
            let v = header.number().ok_or_else(|| {
                malformed(format!(
                    "the ASCII raster ends after {i} of {n} values, or holds a non-number"
                ))
            })?;
            match u8::try_from(v) {
                Ok(v) if v <= max_value => grey.push(v),
                _ => {
                    return Err(malformed(format!(
                        "value {v} of pixel {i} exceeds maxval {max_value}"
                    )));
                }
            }
        }
        grey
    } else {
        // Exactly one whitespace byte separates maxval from the raster.
        let start = header.pos + 1;
        let raster = bytes
            .get(start..)
            .and_then(|rest| rest.get(..n))
            .ok_or_else(|| {
                malformed(format!(
                    "the raster has {} bytes; {width} x {height} pixels need {n}",
                    bytes.len().saturating_sub(start)
                ))
            })?;
        if let Some((i, v)) = raster.iter().enumerate().find(|(_, v)| **v > max_value) {
            return Err(malformed(format!(
                "value {v} of pixel {i} exceeds maxval {max_value}"
            )));
        }
        raster.to_vec()
    };
    Ok(GreyImage {
        width,
        height,
        max_value,
        grey,
        alpha: None,
    })
}

pub(super) fn decode_png(bytes: &[u8], path: &Path) -> Result<GreyImage> {
    let malformed = |e: png::DecodingError| PlanError::MalformedImage {
        path: path.to_path_buf(),
        reason: vpmap_files::decoder_message(&e.to_string()),
    };
    let limits = png::Limits {
        bytes: MAX_CELLS.saturating_mul(4),
    };
    let mut decoder = png::Decoder::new_with_limits(std::io::Cursor::new(bytes), limits);
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(malformed)?;
    let (w, h) = reader.info().size();
    let width = usize::try_from(w).unwrap_or(usize::MAX);
    let height = usize::try_from(h).unwrap_or(usize::MAX);
    let n = checked_cell_count(width, height)?;
    // `None` when the decoded size overflows `usize`: far beyond the cell cap.
    let size = reader.output_buffer_size().ok_or(PlanError::GridTooLarge {
        width,
        height,
        max: MAX_CELLS,
    })?;
    let mut buf = vec![0; size];
    let info = reader.next_frame(&mut buf).map_err(malformed)?;
    let channels = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => {
            return Err(PlanError::UnsupportedImage {
                path: path.to_path_buf(),
                reason: "an indexed-colour PNG that did not expand to RGB".to_owned(),
            });
        }
    };
    let has_alpha = channels % 2 == 0;
    let mut grey = Vec::with_capacity(n);
    let mut alpha = Vec::with_capacity(if has_alpha { n } else { 0 });
    for row in buf.chunks(info.line_size.max(1)).take(height) {
        for px in row.chunks_exact(channels).take(width) {
            let colour = if channels >= 3 { &px[..3] } else { &px[..1] };
            let sum: u32 = colour.iter().map(|&v| u32::from(v)).sum();
            let mean = (sum + colour.len() as u32 / 2) / colour.len() as u32;
            grey.push(u8::try_from(mean).unwrap_or(u8::MAX));
            if has_alpha {
                alpha.push(px.last().copied().unwrap_or(u8::MAX));
            }
        }
    }
    if grey.len() != n {
        return Err(PlanError::MalformedImage {
            path: path.to_path_buf(),
            reason: format!("decoded {} of {n} pixels", grey.len()),
        });
    }
    Ok(GreyImage {
        width,
        height,
        max_value: u8::MAX,
        grey,
        alpha: has_alpha.then_some(alpha),
    })
}

pub(super) fn decode_image(bytes: &[u8], path: &Path) -> Result<GreyImage> {
    match bytes.get(..2) {
        Some(b"P2" | b"P5") => decode_pgm(bytes, path),
        _ if bytes.starts_with(b"\x89PNG\r\n\x1a\n") => decode_png(bytes, path),
        Some([b'P', b'1' | b'3' | b'4' | b'6']) => Err(PlanError::UnsupportedImage {
            path: path.to_path_buf(),
            reason: "a PBM or PPM file; use a greyscale PGM (P2 or P5) or PNG".to_owned(),
        }),
        _ => Err(PlanError::UnsupportedImage {
            path: path.to_path_buf(),
            reason: "neither PGM nor PNG (by its first bytes)".to_owned(),
        }),
    }
}
