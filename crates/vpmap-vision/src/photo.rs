//! Reading a photo: JPEG or PNG only, its size checked in the header before decoding, the
//! decoder's memory limited, and the EXIF orientation applied (as image viewers show it).
//! `vpmap detect` and `vpmap serve` read photos through [`decode_photo`].

use std::io::Cursor;

use image::{DynamicImage, ImageDecoder, ImageFormat, ImageReader, Limits};

use crate::error::{Result, VisionError};
use crate::prepare::{MAX_SIDE_PX, MIN_SIDE_PX};

/// How large a photo [`decode_photo`] accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PhotoLimits {
    /// Largest side, pixels (at most [`MAX_SIDE_PX`]).
    pub max_side_px: u32,
    /// Most pixels.
    pub max_pixels: u64,
    /// Most memory the decoder may allocate, bytes.
    pub max_decode_bytes: u64,
}

impl Default for PhotoLimits {
    /// Up to [`MAX_SIDE_PX`] on a side, 150 megapixels, 2 GiB of decoder memory.
    fn default() -> Self {
        Self {
            max_side_px: MAX_SIDE_PX,
            max_pixels: 150_000_000,
            max_decode_bytes: 2 << 30,
        }
    }
}

/// A decoded photo.
#[derive(Clone, Debug)]
pub struct Photo {
    /// The pixels, turned upright as the EXIF orientation says.
    pub image: DynamicImage,
    /// Whether the EXIF orientation turned or flipped it.
    pub reoriented: bool,
}

/// Decode the bytes of a JPEG or PNG photo (see the [module docs](self)).
///
/// # Errors
/// [`VisionError::EmptyPhoto`], [`VisionError::NotAPhoto`],
/// [`VisionError::UnsupportedFormat`], [`VisionError::PhotoSize`] (checked from the header,
/// before decoding) or [`VisionError::Decode`] (truncated or corrupt data, or more memory
/// than the limit).
///
/// # Example
/// ```
/// use vpmap_vision::photo::{decode_photo, PhotoLimits};
/// assert!(decode_photo(b"hello", &PhotoLimits::default()).is_err());
/// ```
pub fn decode_photo(bytes: &[u8], limits: &PhotoLimits) -> Result<Photo> {
    if bytes.is_empty() {
        return Err(VisionError::EmptyPhoto);
    }
    let format = match image::guess_format(bytes) {
        Ok(f @ (ImageFormat::Jpeg | ImageFormat::Png)) => f,
        Ok(other) => {
            return Err(VisionError::UnsupportedFormat {
                format: other
                    .extensions_str()
                    .first()
                    .copied()
                    .unwrap_or("?")
                    .to_owned(),
            });
        }
        Err(_) => return Err(VisionError::NotAPhoto { bytes: bytes.len() }),
    };
    let kind = if format == ImageFormat::Jpeg {
        "JPEG"
    } else {
        "PNG"
    };
    let decode_error = |e: image::ImageError| VisionError::Decode {
        format: kind,
        message: vpmap_files::decoder_message(&e.to_string()),
    };
    let max_side = limits.max_side_px.min(MAX_SIDE_PX);
    // The header's size first: the decoder would refuse an absurd size with a vaguer message.
    let (width, height) = ImageReader::with_format(Cursor::new(bytes), format)
        .into_dimensions()
        .map_err(decode_error)?;
    if width < MIN_SIDE_PX
        || height < MIN_SIDE_PX
        || width > max_side
        || height > max_side
        || u64::from(width) * u64::from(height) > limits.max_pixels
    {
        return Err(VisionError::PhotoSize {
            width,
            height,
            min: MIN_SIDE_PX,
            max: max_side,
            max_megapixels: limits.max_pixels / 1_000_000,
        });
    }
    if format == ImageFormat::Jpeg && !jpeg_is_complete(bytes) {
        // The decoder would fill the missing rows with grey and say nothing.
        return Err(VisionError::Decode {
            format: kind,
            message: format!(
                "the file is truncated: its {} bytes end without the JPEG end-of-image marker after the last scan (was it cut short when copied or downloaded?)",
                bytes.len()
            ),
        });
    }
    let mut reader = ImageReader::with_format(Cursor::new(bytes), format);
    let mut decoder_limits = Limits::default();
    decoder_limits.max_image_width = Some(max_side);
    decoder_limits.max_image_height = Some(max_side);
    decoder_limits.max_alloc = Some(limits.max_decode_bytes);
    reader.limits(decoder_limits);
    let mut decoder = reader.into_decoder().map_err(decode_error)?;
    let orientation = decoder
        .orientation()
        .unwrap_or(image::metadata::Orientation::NoTransforms);
    let mut image = DynamicImage::from_decoder(decoder).map_err(decode_error)?;
    image.apply_orientation(orientation);
    Ok(Photo {
        image,
        reoriented: orientation != image::metadata::Orientation::NoTransforms,
    })
}

/// Whether a JPEG's data end with the end-of-image marker (`FF D9`) after its last
/// start-of-scan marker (`FF DA`). Entropy-coded data escape every `FF` byte, so neither
/// marker can appear inside a scan; an embedded thumbnail's markers come before the main
/// image's scans. Bytes after the end marker (padding some cameras add) are allowed.
fn jpeg_is_complete(bytes: &[u8]) -> bool {
    let last_scan = bytes.windows(2).rposition(|w| w == [0xFF, 0xDA]);
    last_scan.is_some_and(|at| {
        bytes
            .get(at..)
            .is_some_and(|scan| scan.windows(2).any(|w| w == [0xFF, 0xD9]))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(width: u32, height: u32) -> Vec<u8> {
        let mut out = Vec::new();
        let image = DynamicImage::new_luma8(width, height);
        let _ = image.write_to(&mut Cursor::new(&mut out), ImageFormat::Png);
        out
    }

    #[test]
    fn bad_photos_are_named() {
        let limits = PhotoLimits::default();
        assert!(matches!(
            decode_photo(b"", &limits),
            Err(VisionError::EmptyPhoto)
        ));
        assert!(matches!(
            decode_photo(b"hello, world", &limits),
            Err(VisionError::NotAPhoto { bytes: 12 })
        ));
        let gif = decode_photo(b"GIF89a\x01\x00\x01\x00", &limits);
        assert!(
            matches!(gif, Err(VisionError::UnsupportedFormat { ref format }) if format == "gif")
        );
        let tiny = decode_photo(&png(8, 8), &limits);
        assert!(matches!(
            tiny,
            Err(VisionError::PhotoSize {
                width: 8,
                height: 8,
                ..
            })
        ));
        let good = png(40, 30);
        let photo = decode_photo(&good, &limits).map_err(|e| e.to_string());
        assert_eq!(
            photo.map(|p| (p.image.width(), p.reoriented)),
            Ok((40, false))
        );
        let truncated = decode_photo(&good[..good.len() / 2], &limits);
        assert!(matches!(
            truncated,
            Err(VisionError::Decode { format: "PNG", .. })
        ));
        let small = PhotoLimits {
            max_side_px: 32,
            ..limits
        };
        assert!(matches!(
            decode_photo(&good, &small),
            Err(VisionError::PhotoSize { max: 32, .. })
        ));
        // A corrupt header checksum: the message names the chunk, not the decoder's types.
        let mut bad_crc = good.clone();
        if let Some(b) = bad_crc.get_mut(29) {
            *b ^= 0xFF; // first byte of the IHDR chunk's CRC (8 signature + 8 + 13 bytes in)
        }
        let message = decode_photo(&bad_crc, &limits)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("IHDR") && !message.contains("ChunkType"),
            "{message}"
        );
    }

    fn jpeg(width: u32, height: u32) -> Vec<u8> {
        let mut out = Vec::new();
        let image = DynamicImage::ImageRgb8(image::RgbImage::from_fn(width, height, |x, y| {
            image::Rgb([(x * 7) as u8, (y * 5) as u8, ((x + y) * 3) as u8])
        }));
        let _ = image.write_to(&mut Cursor::new(&mut out), ImageFormat::Jpeg);
        out
    }

    #[test]
    fn a_truncated_jpeg_is_refused_and_a_padded_one_read() {
        let limits = PhotoLimits::default();
        let whole = jpeg(64, 48);
        assert!(decode_photo(&whole, &limits).is_ok());
        // Zero padding after the end marker, as some cameras write, is fine.
        let mut padded = whole.clone();
        padded.extend_from_slice(&[0; 64]);
        assert!(decode_photo(&padded, &limits).is_ok());
        // Cut inside the scan: the decoder alone would return a partly grey photo.
        for keep in [whole.len() - 2, whole.len() * 3 / 4] {
            let cut = decode_photo(&whole[..keep], &limits).map(|_| ());
            let message = cut.unwrap_err().to_string();
            assert!(
                message.contains("truncated") && message.contains("JPEG"),
                "{keep}: {message}"
            );
        }
    }
}
