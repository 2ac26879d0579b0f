//! A photo, as `vpmap detect` and `/api/detect` read it: JPEG or PNG decoding with its size
//! checked from the header, EXIF orientation, then line segments (LSD), the vanishing points
//! and the scene made of them. Only small photos: at most 256 pixels a side, refused by
//! `decode_photo`'s own header check before decoding.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vpmap_vision::photo::{PhotoLimits, decode_photo};
use vpmap_vision::scene::detected_scene;
use vpmap_vision::{DetectOptions, detect_from_segments, detect_segments};

fuzz_target!(|data: &[u8]| {
    let limits = PhotoLimits {
        max_side_px: 256,
        max_pixels: 256 * 256,
        max_decode_bytes: 16 << 20,
    };
    let Ok(photo) = decode_photo(data, &limits) else {
        return;
    };
    let image = &photo.image;
    let options = DetectOptions::default();
    let Ok(segments) = detect_segments(image, &options) else {
        return;
    };
    for s in &segments {
        assert!(
            s.start_px.iter().chain(&s.end_px).all(|c| c.is_finite()),
            "a segment with a non-finite end: {s:?}"
        );
    }
    if let Ok(detection) = detect_from_segments(segments, [image.width(), image.height()], &options)
    {
        let _ = detected_scene(&detection);
    }
});
