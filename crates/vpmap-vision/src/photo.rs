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
    let (format, kind) = sniff(bytes)?;
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
    // Turning a photo a quarter turn copies its pixels: the peak is twice the decoded size,
    // and the decoder's limit covers only the first copy.
    let pixels_bytes = decoder.total_bytes();
    let copies = if turns_quarter(orientation) { 2 } else { 1 };
    if pixels_bytes.saturating_mul(copies) > limits.max_decode_bytes {
        return Err(VisionError::Decode {
            format: kind,
            message: format!(
                "its {width} x {height} pixels take {} MB decoded{}, more than the {} MB limit",
                pixels_bytes.saturating_mul(copies) / 1_000_000,
                if copies == 2 {
                    " and twice that to turn them upright as the EXIF orientation says"
                } else {
                    ""
                },
                limits.max_decode_bytes / 1_000_000
            ),
        });
    }
    let mut image = DynamicImage::from_decoder(decoder).map_err(decode_error)?;
    image.apply_orientation(orientation);
    Ok(Photo {
        image,
        reoriented: orientation != image::metadata::Orientation::NoTransforms,
    })
}

/// Whether an EXIF orientation swaps the width and the height (a quarter turn, so the
/// image is copied rather than turned in place).
fn turns_quarter(orientation: image::metadata::Orientation) -> bool {
    use image::metadata::Orientation as O;
    matches!(
        orientation,
        O::Rotate90 | O::Rotate270 | O::Rotate90FlipH | O::Rotate270FlipH
    )
}

/// A photo's size as it is shown (width and height swapped when its EXIF orientation turns
/// it a quarter turn), read from its header without decoding the pixels: to compare it with a
/// scene's before spending the time and memory of decoding.
///
/// # Errors
/// As [`decode_photo`] for bytes that are no JPEG or PNG, or whose header is corrupt.
///
/// # Example
/// ```
/// use vpmap_vision::photo::photo_dimensions;
/// let mut png = Vec::new();
/// image::DynamicImage::new_luma8(40, 30)
///     .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
///     .unwrap();
/// assert_eq!(photo_dimensions(&png).unwrap(), (40, 30));
/// ```
pub fn photo_dimensions(bytes: &[u8]) -> Result<(u32, u32)> {
    let (format, kind) = sniff(bytes)?;
    let decode_error = |e: image::ImageError| VisionError::Decode {
        format: kind,
        message: vpmap_files::decoder_message(&e.to_string()),
    };
    let mut decoder = ImageReader::with_format(Cursor::new(bytes), format)
        .into_decoder()
        .map_err(decode_error)?;
    let (width, height) = decoder.dimensions();
    let orientation = decoder
        .orientation()
        .unwrap_or(image::metadata::Orientation::NoTransforms);
    Ok(if turns_quarter(orientation) {
        (height, width)
    } else {
        (width, height)
    })
}

/// The format of a photo's bytes (JPEG or PNG) and its name in messages.
fn sniff(bytes: &[u8]) -> Result<(ImageFormat, &'static str)> {
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
    Ok((format, kind))
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

    /// The PNG of `png(width, height)` with an `eXIf` chunk saying EXIF orientation
    /// `orientation` (6: turn a quarter clockwise), inserted after `IHDR`.
    fn png_with_orientation(width: u32, height: u32, orientation: u16) -> Vec<u8> {
        fn crc32(bytes: &[u8]) -> u32 {
            let mut crc = 0xFFFF_FFFFu32;
            for &b in bytes {
                crc ^= u32::from(b);
                for _ in 0..8 {
                    crc = if crc & 1 == 1 {
                        (crc >> 1) ^ 0xEDB8_8320
                    } else {
                        crc >> 1
                    };
                }
            }
            !crc
        }
        let plain = png(width, height);
        // Big-endian TIFF: one IFD entry, tag 0x0112 (orientation), SHORT, count 1.
        let mut exif =
            b"MM\x00\x2a\x00\x00\x00\x08\x00\x01\x01\x12\x00\x03\x00\x00\x00\x01".to_vec();
        exif.extend(orientation.to_be_bytes());
        exif.extend([0, 0, 0, 0, 0, 0]);
        let mut chunk = b"eXIf".to_vec();
        chunk.extend(&exif);
        let mut out = plain[..33].to_vec(); // signature (8) + IHDR (4 + 4 + 13 + 4)
        out.extend(u32::try_from(exif.len()).unwrap_or(0).to_be_bytes());
        out.extend(&chunk);
        out.extend(crc32(&chunk).to_be_bytes());
        out.extend(&plain[33..]);
        out
    }

    /// Regression: a large photo with an EXIF quarter turn peaked at twice the decoder's
    /// memory limit (the turn copies the pixels); its header's size is the turned one.
    #[test]
    fn a_quarter_turn_counts_twice_against_the_decoder_limit() {
        let turned = png_with_orientation(1000, 600, 6);
        assert_eq!(photo_dimensions(&turned).ok(), Some((600, 1000)));
        assert_eq!(photo_dimensions(&png(1000, 600)).ok(), Some((1000, 600)));
        // 600,000 bytes of grey pixels: one copy fits in 800,000 bytes, two do not.
        let limits = PhotoLimits {
            max_decode_bytes: 800_000,
            ..PhotoLimits::default()
        };
        let upright = decode_photo(&png(1000, 600), &limits).map(|p| p.image.width());
        assert_eq!(upright.ok(), Some(1000));
        let message = decode_photo(&turned, &limits)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("EXIF orientation") && message.contains("limit"),
            "{message}"
        );
        let roomy = PhotoLimits {
            max_decode_bytes: 1_300_000,
            ..PhotoLimits::default()
        };
        let photo = decode_photo(&turned, &roomy).map(|p| (p.image.width(), p.reoriented));
        assert_eq!(photo.ok(), Some((600, true)));
    }
}
