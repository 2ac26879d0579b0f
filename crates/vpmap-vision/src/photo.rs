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
    /// What the EXIF says of the lens (empty without EXIF).
    pub exif: ExifLens,
}

/// The lens fields of a photo's EXIF, as read (not yet checked: see
/// [`Photo::exif_focal_prior`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExifLens {
    /// `FocalLengthIn35mmFilm`, millimetres.
    pub focal_35mm: Option<f64>,
    /// `FocalLength`, millimetres (of the real lens, which without the sensor's size gives no
    /// focal length in pixels).
    pub focal_mm: Option<f64>,
    /// Why the EXIF could not be read, when it could not (the photo is still read).
    pub unreadable: Option<String>,
}

/// The relative standard deviation of a focal length from EXIF's 35 mm equivalent: makers round
/// it to a whole millimetre and compute it from their crop factor, and the conversion by the
/// diagonal is exact only for a sensor of the 36 x 24 mm film's shape (a 4:3 sensor's
/// equivalent by width differs from it by diagonal about 3 %).
pub const EXIF_FOCAL_SD: f64 = 0.04;

/// The range of 35 mm equivalent focal lengths believed, millimetres: from fisheye phone lenses
/// to long telephotos.
pub const EXIF_FOCAL_35MM_RANGE: (f64, f64) = (8.0, 1200.0);

/// The diagonal of 35 mm film (36 x 24 mm), millimetres.
const FILM_DIAGONAL_MM: f64 = 43.266_615_305_567_87;

/// Most bytes of EXIF read.
const MAX_EXIF_BYTES: usize = 1 << 20;

impl Photo {
    /// The focal length the EXIF gives, as a prior `(focal_px, relative sd)` for a photo of
    /// this size: the 35 mm equivalent times the image diagonal over the film's (as COLMAP
    /// converts it), with [`EXIF_FOCAL_SD`]; or why none is used (`Err`, a message naming the
    /// value): no EXIF focal length, a 35 mm value missing (only the real lens's, which needs the
    /// sensor's size) or outside [`EXIF_FOCAL_35MM_RANGE`], or EXIF that could not be read.
    /// `Ok(None)` when the photo has no EXIF lens fields at all.
    ///
    /// # Errors
    /// The message for a focal length that is present but not used.
    pub fn exif_focal_prior(&self) -> std::result::Result<Option<(f64, f64)>, String> {
        if let Some(why) = &self.exif.unreadable {
            return Err(format!(
                "its EXIF could not be read ({why}), so it gives no focal length"
            ));
        }
        match (self.exif.focal_35mm, self.exif.focal_mm) {
            (None, None) => Ok(None),
            (None, Some(mm)) => Err(format!(
                "its EXIF gives the lens's focal length ({mm} mm) but no 35 mm equivalent, which needs the sensor's size: not used"
            )),
            (Some(f35), _) => {
                let (lo, hi) = EXIF_FOCAL_35MM_RANGE;
                if !(f35.is_finite() && (lo..=hi).contains(&f35)) {
                    return Err(format!(
                        "its EXIF 35 mm equivalent focal length of {f35} mm is outside {lo}-{hi} mm: not used"
                    ));
                }
                let diagonal = f64::from(self.image.width()).hypot(f64::from(self.image.height()));
                Ok(Some((f35 * diagonal / FILM_DIAGONAL_MM, EXIF_FOCAL_SD)))
            }
        }
    }
}

/// The lens fields of raw EXIF data (a TIFF structure, with or without JPEG's `Exif\0\0`).
fn read_exif(raw: &[u8]) -> ExifLens {
    if raw.len() > MAX_EXIF_BYTES {
        return ExifLens {
            unreadable: Some(format!(
                "{} bytes of EXIF, more than the {MAX_EXIF_BYTES} read",
                raw.len()
            )),
            ..ExifLens::default()
        };
    }
    let tiff = raw.strip_prefix(b"Exif\0\0").unwrap_or(raw);
    let exif = match exif::Reader::new().read_raw(tiff.to_vec()) {
        Ok(e) => e,
        Err(e) => {
            return ExifLens {
                unreadable: Some(e.to_string()),
                ..ExifLens::default()
            };
        }
    };
    let number = |tag: exif::Tag| {
        exif.get_field(tag, exif::In::PRIMARY)
            .and_then(|f| match &f.value {
                exif::Value::Rational(v) => v.first().map(exif::Rational::to_f64),
                exif::Value::SRational(v) => v.first().map(exif::SRational::to_f64),
                other => other.get_uint(0).map(f64::from),
            })
    };
    ExifLens {
        // A 35 mm value of 0 means "unknown" (EXIF 2.3).
        focal_35mm: number(exif::Tag::FocalLengthIn35mmFilm).filter(|v| *v != 0.0),
        focal_mm: number(exif::Tag::FocalLength),
        unreadable: None,
    }
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
    let exif = match decoder.exif_metadata() {
        Ok(Some(raw)) => read_exif(&raw),
        Ok(None) => ExifLens::default(),
        Err(e) => ExifLens {
            unreadable: Some(e.to_string()),
            ..ExifLens::default()
        },
    };
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
        exif,
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

    /// A 64 x 48 JPEG whose EXIF holds the given lens fields (or `raw` bytes as its EXIF).
    fn jpeg_with_exif(
        focal_35mm: Option<u16>,
        focal_mm: Option<(u32, u32)>,
        raw: Option<&[u8]>,
    ) -> Vec<u8> {
        use image::ImageEncoder as _;
        let exif = raw.map_or_else(
            || {
                let f35 = focal_35mm.map(|v| exif::Field {
                    tag: exif::Tag::FocalLengthIn35mmFilm,
                    ifd_num: exif::In::PRIMARY,
                    value: exif::Value::Short(vec![v]),
                });
                let fmm = focal_mm.map(|(n, d)| exif::Field {
                    tag: exif::Tag::FocalLength,
                    ifd_num: exif::In::PRIMARY,
                    value: exif::Value::Rational(vec![exif::Rational { num: n, denom: d }]),
                });
                let mut w = exif::experimental::Writer::new();
                for f in f35.iter().chain(fmm.iter()) {
                    w.push_field(f);
                }
                let mut out = Cursor::new(Vec::new());
                w.write(&mut out, true).unwrap_or_else(|e| panic!("{e}"));
                out.into_inner()
            },
            <[u8]>::to_vec,
        );
        let mut out = Vec::new();
        let mut enc = image::codecs::jpeg::JpegEncoder::new(&mut out);
        enc.set_exif_metadata(exif)
            .unwrap_or_else(|e| panic!("{e}"));
        let pixels = vec![128u8; 64 * 48];
        enc.write_image(&pixels, 64, 48, image::ExtendedColorType::L8)
            .unwrap_or_else(|e| panic!("{e}"));
        out
    }

    #[test]
    fn exif_focal_length_becomes_a_prior_or_says_why_not() {
        let limits = PhotoLimits::default();
        let read = |bytes: Vec<u8>| decode_photo(&bytes, &limits).unwrap_or_else(|e| panic!("{e}"));
        // 28 mm equivalent on a 64 x 48 photo: 28 x 80 / 43.27 = 51.8 px, 4 %.
        let p = read(jpeg_with_exif(Some(28), Some((42, 10)), None));
        assert_eq!(p.exif.focal_35mm, Some(28.0));
        assert_eq!(p.exif.focal_mm, Some(4.2));
        let (f, sd) = p
            .exif_focal_prior()
            .unwrap_or_else(|e| panic!("{e}"))
            .unwrap_or_default();
        assert!((f - 28.0 * 80.0 / 36f64.hypot(24.0)).abs() < 1e-9, "{f}");
        assert!((sd - EXIF_FOCAL_SD).abs() < 1e-12);
        // Only the real lens's focal length: said, not used.
        let p = read(jpeg_with_exif(None, Some((42, 10)), None));
        let e = p.exif_focal_prior().err().unwrap_or_default();
        assert!(e.contains("4.2 mm") && e.contains("35 mm"), "{e}");
        // 0 means unknown in EXIF; 10,000 mm is absurd.
        let p = read(jpeg_with_exif(Some(0), None, None));
        assert_eq!(p.exif_focal_prior(), Ok(None));
        let p = read(jpeg_with_exif(Some(10_000), None, None));
        let e = p.exif_focal_prior().err().unwrap_or_default();
        assert!(e.contains("10000 mm") && e.contains("outside"), "{e}");
        // A broken IFD: the photo is read, its EXIF said to be unreadable.
        let p = read(jpeg_with_exif(
            None,
            None,
            Some(b"II*\0\xff\xff\xff\x7f garbage"),
        ));
        let e = p.exif_focal_prior().err().unwrap_or_default();
        assert!(e.contains("could not be read"), "{e}");
        // No EXIF at all.
        let p = read(png(40, 30));
        assert_eq!(p.exif_focal_prior(), Ok(None));
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
