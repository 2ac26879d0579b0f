//! The photos the page snaps clicks on (`POST /api/photo`), kept so that a click does not
//! send its photo again: a least-recently-used store of at most [`MAX_PHOTOS`] photos and
//! [`MAX_PHOTO_BYTES`] of pixels (the newest photo is always kept, whatever its size). Each
//! photo has an id (`p1`, `p2`, ... in upload order, never reused while the server runs);
//! an evicted or unknown id is answered with 404, and the page then sends the photo again.

use std::sync::{Arc, Mutex, OnceLock};

use image::DynamicImage;
use vpmap_vision::Segment;
use vpmap_vision::snap::SnapImage;

/// Most photos kept.
pub const MAX_PHOTOS: usize = 4;
/// Most bytes of pixels kept: what the kept photos really hold. Each is kept as 8-bit grey
/// (whatever the file's type: a 16-bit RGBA photo decodes to 8 bytes a pixel), twice (the
/// snapping copy and the image its segments are found on), 2 bytes a pixel (its segments,
/// a few hundred kilobytes at most, are not counted).
pub const MAX_PHOTO_BYTES: u64 = 400 << 20;

/// Rows converted to grey at once (a band of the decoded photo is copied in its own type,
/// then converted).
const GREY_BAND_ROWS: u32 = 256;

/// One kept photo.
pub(crate) struct StoredPhoto {
    /// Its pixels as snapping reads them (8-bit grey).
    pub(crate) snap: SnapImage,
    /// The photo in 8-bit grey (for the segments of box proposals).
    pub(crate) image: DynamicImage,
    /// Its line segments, found on first use.
    pub(crate) segments: OnceLock<Result<Vec<Segment>, String>>,
    /// Bytes of pixels it holds, counted against [`MAX_PHOTO_BYTES`].
    bytes: u64,
}

/// `image` in 8-bit grey (the `image` crate's conversion, Rec. 709 luma), converted a band
/// of rows at a time: no full-size copy in another type is made.
fn grey8(image: &DynamicImage) -> image::GrayImage {
    if let DynamicImage::ImageLuma8(g) = image {
        return g.clone();
    }
    let (width, height) = (image.width(), image.height());
    let mut out = Vec::with_capacity(width as usize * height as usize);
    let mut y = 0;
    while y < height {
        let rows = GREY_BAND_ROWS.min(height - y);
        out.extend_from_slice(image.crop_imm(0, y, width, rows).to_luma8().as_raw());
        y += rows;
    }
    // The buffer holds exactly width x height bytes, so this is never the fallback.
    image::GrayImage::from_raw(width, height, out)
        .unwrap_or_else(|| image::GrayImage::new(width, height))
}

impl StoredPhoto {
    /// Keep `image` as 8-bit grey (see [`MAX_PHOTO_BYTES`]); the decoded image may be
    /// dropped as soon as this returns.
    pub(crate) fn new(image: &DynamicImage) -> Self {
        let image = DynamicImage::ImageLuma8(grey8(image));
        let snap = SnapImage::new(&image);
        let bytes = (image.as_bytes().len() + snap.pixel_bytes()) as u64;
        Self {
            snap,
            image,
            segments: OnceLock::new(),
            bytes,
        }
    }

    /// Bytes of pixels it holds.
    pub(crate) fn bytes(&self) -> u64 {
        self.bytes
    }
}

/// The store: most recently used last.
#[derive(Default)]
pub(crate) struct PhotoStore {
    inner: Mutex<Inner>,
}

#[derive(Default)]
struct Inner {
    next: u64,
    photos: Vec<(String, Arc<StoredPhoto>)>,
}

impl PhotoStore {
    /// Keep `photo`, evicting the least recently used beyond the limits; its id.
    pub(crate) fn insert(&self, photo: StoredPhoto) -> String {
        let mut inner = self
            .inner
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        inner.next += 1;
        let id = format!("p{}", inner.next);
        inner.photos.push((id.clone(), Arc::new(photo)));
        loop {
            let total: u64 = inner.photos.iter().map(|(_, p)| p.bytes()).sum();
            if inner.photos.len() > 1
                && (inner.photos.len() > MAX_PHOTOS || total > MAX_PHOTO_BYTES)
            {
                inner.photos.remove(0);
            } else {
                break;
            }
        }
        id
    }

    /// The photo of `id` (now the most recently used), if kept.
    pub(crate) fn get(&self, id: &str) -> Option<Arc<StoredPhoto>> {
        let mut inner = self
            .inner
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let k = inner.photos.iter().position(|(i, _)| i == id)?;
        let entry = inner.photos.remove(k);
        let photo = Arc::clone(&entry.1);
        inner.photos.push(entry);
        Some(photo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::GrayImage;

    fn photo() -> StoredPhoto {
        StoredPhoto::new(&DynamicImage::ImageLuma8(GrayImage::new(4, 3)))
    }

    #[test]
    fn a_16_bit_rgba_photo_counts_the_bytes_it_holds() {
        // Kept at 8 + 3 bytes a pixel it was counted at 6 (issue 40).
        let rgba16 = DynamicImage::ImageRgba16(image::ImageBuffer::from_fn(300, 200, |x, y| {
            image::Rgba([(x * 200) as u16, (y * 300) as u16, 40_000, 65_535])
        }));
        let photo = StoredPhoto::new(&rgba16);
        let held = photo.image.as_bytes().len() + photo.snap.pixel_bytes();
        assert_eq!(photo.bytes(), held as u64);
        assert_eq!(held, 2 * 300 * 200);
        // The grey levels are the image crate's own conversion, band by band.
        assert_eq!(
            photo.image.as_bytes(),
            rgba16.to_luma8().as_raw().as_slice()
        );
    }

    #[test]
    fn the_least_recently_used_photo_goes_first() {
        let store = PhotoStore::default();
        let ids: Vec<String> = (0..MAX_PHOTOS).map(|_| store.insert(photo())).collect();
        assert_eq!(ids[0], "p1");
        // Using the first makes the second the oldest.
        assert!(store.get(&ids[0]).is_some());
        let newest = store.insert(photo());
        assert!(store.get(&ids[1]).is_none());
        assert!(store.get(&ids[0]).is_some() && store.get(&newest).is_some());
        assert!(store.get("p99").is_none());
    }
}
