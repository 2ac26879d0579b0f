//! Reading a photo: JPEG or PNG only, its size checked in the header before decoding, the
//! decoder's memory limited, and the EXIF orientation applied (as image viewers show it).
//! `vpmap detect` and `vpmap serve` read photos through [`decode_photo`].

use std::io::Cursor;

use image::{DynamicImage, ImageDecoder, ImageFormat, ImageReader, Limits};

use crate::error::{Result, VisionError};
use crate::{MAX_SIDE_PX, MIN_SIDE_PX};

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
        message: e
            .to_string()
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" "),
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
    }
}
