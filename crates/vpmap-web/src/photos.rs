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
/// Most bytes of pixels kept (each photo counts its decoded pixels twice: the snapping copy
/// and the image its segments are detected on).
pub const MAX_PHOTO_BYTES: u64 = 400 << 20;

/// One kept photo.
pub(crate) struct StoredPhoto {
    /// Its pixels as snapping reads them.
    pub(crate) snap: SnapImage,
    /// The decoded image (for the segments of box proposals).
    pub(crate) image: DynamicImage,
    /// Its line segments at full size, found on first use.
    pub(crate) segments: OnceLock<Result<Vec<Segment>, String>>,
    /// Bytes it counts against [`MAX_PHOTO_BYTES`].
    bytes: u64,
}

impl StoredPhoto {
    pub(crate) fn new(image: DynamicImage) -> Self {
        let snap = SnapImage::new(&image);
        let bytes = 2 * u64::from(image.width()) * u64::from(image.height()) * 3;
        Self {
            snap,
            image,
            segments: OnceLock::new(),
            bytes,
        }
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
            let total: u64 = inner.photos.iter().map(|(_, p)| p.bytes).sum();
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
        StoredPhoto::new(DynamicImage::ImageLuma8(GrayImage::new(4, 3)))
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
