//! `POST /api/detect`.

use std::sync::OnceLock;

use crate::{assert_alive, base64_decode, get, request};

/// The example photo, from `/api/example`.
fn example_photo() -> &'static [u8] {
    static PHOTO: OnceLock<Vec<u8>> = OnceLock::new();
    PHOTO.get_or_init(|| {
        let v = get("/api/example").json();
        base64_decode(v["photo_png_base64"].as_str().unwrap())
    })
}

fn post_image(target: &str, content_type: &str, body: &[u8]) -> crate::Reply {
    request("POST", target, &[("Content-Type", content_type)], body)
}

/// One PNG chunk: length, type, data, CRC.
fn chunk(png: &mut Vec<u8>, kind: [u8; 4], data: &[u8]) {
    png.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let mut typed = kind.to_vec();
    typed.extend_from_slice(data);
    png.extend_from_slice(&typed);
    png.extend_from_slice(&crc32fast::hash(&typed).to_be_bytes());
}

/// A well-formed PNG claiming `width` x `height` RGB pixels, whose image data holds only a
/// few bytes (a zlib stream of nothing): its header is all a decoder can read.
fn png_header(width: u32, height: u32) -> Vec<u8> {
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    chunk(&mut png, *b"IHDR", &ihdr);
    chunk(
        &mut png,
        *b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    );
    chunk(&mut png, *b"IEND", &[]);
    png
}

#[test]
fn example_photo_gives_three_vanishing_points_and_a_scene() {
    let reply = post_image("/api/detect", "image/png", example_photo());
    assert_eq!(
        reply.status,
        200,
        "{}",
        String::from_utf8_lossy(&reply.body)
    );
    let v = reply.json();
    let vps = v["vanishing_points"].as_array().unwrap();
    assert_eq!(vps.len(), 3);
    assert_eq!(v["perspective"], "3pp");
    assert_eq!(vps.iter().filter(|p| p["vertical"] == true).count(), 1);
    let segments = v["segments"].as_array().unwrap();
    assert!(segments.len() > 20, "{}", segments.len());
    for p in vps {
        for i in p["segments"].as_array().unwrap() {
            assert!((i.as_u64().unwrap() as usize) < segments.len());
        }
    }
    // The office was photographed with a 1100 px lens at 25 degrees pitch.
    let f = v["focal_px"].as_f64().unwrap();
    // Each direction's own point: its edges alone. The office is a Manhattan room, so they
    // meet close to the frame's point; its angle and its pixel follow from its direction.
    let pp = v["principal_point"].as_array().unwrap();
    let (cx, cy) = (pp[0].as_f64().unwrap(), pp[1].as_f64().unwrap());
    let unit = |a: &serde_json::Value| -> [f64; 3] {
        let a: Vec<f64> = a
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        [a[0], a[1], a[2]]
    };
    for p in vps {
        let own = &p["own_point"];
        assert!(own["edges"].as_u64().unwrap() >= 2, "{own}");
        let (d, o) = (unit(&p["direction_camera"]), unit(&own["direction_camera"]));
        let dot = (d[0] * o[0] + d[1] * o[1] + d[2] * o[2]).clamp(-1.0, 1.0);
        let angle = dot.abs().acos().to_degrees();
        let said = own["from_frame_deg"].as_f64().unwrap();
        assert!((angle - said).abs() < 1e-6, "{angle} against {said}");
        assert!(said < 1.0, "own point {said} degrees from the frame's");
        if let Some(point) = own["point"].as_array() {
            let (x, y) = (point[0].as_f64().unwrap(), point[1].as_f64().unwrap());
            assert!(
                (x - (cx + f * o[0] / o[2])).abs() < 1e-6 * x.abs().max(1.0),
                "{own}"
            );
            assert!(
                (y - (cy + f * o[1] / o[2])).abs() < 1e-6 * y.abs().max(1.0),
                "{own}"
            );
        }
    }
    assert!((f / 1100.0 - 1.0).abs() < 0.05, "focal {f}");
    assert_eq!(v["image"]["width"], 1600);
    // The scene is what `vpmap detect` writes: it calibrates, with three vanishing points.
    let scene = &v["scene"];
    assert_eq!(scene["version"], 1);
    assert_eq!(scene["perspective"], "3pp");
    assert_eq!(scene["vanishing_points"].as_array().unwrap().len(), 3);
    assert_eq!(scene["objects"].as_array().unwrap().len(), 0);
    assert!((scene["focal_px"].as_f64().unwrap() - f).abs() < 1e-3);
    // It builds (an empty map, but a camera).
    let built = crate::post_json("/api/build", &scene.to_string()).json();
    let pitch = built["camera"]["pitch_deg"].as_f64().unwrap();
    assert!((pitch - 25.0).abs() < 2.0, "pitch {pitch}");
}

#[test]
fn known_intrinsics_are_used() {
    let reply = post_image(
        "/api/detect?focal_px=1100&principal_point=800,600",
        "application/octet-stream",
        example_photo(),
    );
    let v = reply.json();
    assert_eq!(v["focal_px"], 1100.0);
    assert_eq!(v["principal_point"], serde_json::json!([800.0, 600.0]));
    assert_eq!(v["focal_estimated"], false);
}

#[test]
fn bad_photos_are_refused_and_the_server_keeps_serving() {
    // Empty body, wrong content type, not an image, another format.
    assert!(
        post_image("/api/detect", "image/png", b"")
            .error(400)
            .contains("empty")
    );
    let message = post_image("/api/detect", "text/plain", example_photo()).error(400);
    assert!(message.contains("text/plain"), "{message}");
    let message = post_image("/api/detect", "image/jpeg", b"hello, this is text").error(400);
    assert!(message.contains("not a JPEG or PNG"), "{message}");
    let message = post_image(
        "/api/detect",
        "image/png",
        b"GIF89a\x10\x00\x10\x00\x00\x00",
    )
    .error(400);
    assert!(message.contains("gif"), "{message}");
    // Huge dimensions in the header: refused before any pixel is decoded.
    for (w, h) in [(9000, 9000), (100_000, 100_000), (8000, 8001)] {
        let message = post_image("/api/detect", "image/png", &png_header(w, h)).error(400);
        assert!(message.contains(&format!("{w} x {h}")), "{message}");
    }
    // A header with no pixels.
    let message = post_image("/api/detect", "image/png", &png_header(640, 480)).error(400);
    assert!(message.contains("cannot decode"), "{message}");
    // Too small to find anything in.
    let mut tiny = Vec::new();
    image::RgbImage::new(8, 8)
        .write_to(
            &mut std::io::Cursor::new(&mut tiny),
            image::ImageFormat::Png,
        )
        .unwrap();
    let message = post_image("/api/detect", "image/png", &tiny).error(400);
    assert!(message.contains("8 x 8"), "{message}");
    // A blank photo has no edges.
    let mut blank = Vec::new();
    image::RgbImage::from_pixel(320, 240, image::Rgb([128, 128, 128]))
        .write_to(
            &mut std::io::Cursor::new(&mut blank),
            image::ImageFormat::Png,
        )
        .unwrap();
    let message = post_image("/api/detect", "image/png", &blank).error(400);
    assert!(message.contains("line segments"), "{message}");
    // Bad parameters.
    for (query, needle) in [
        ("focal_px=-5", "focal_px"),
        ("focal_px=5", "focal_px"),
        ("principal_point=1,2,3", "principal_point"),
        ("principal_point=5000,5000", "outside"),
        ("two_point_tolerance=90", "two_point_tolerance"),
        ("focal=1100", "focal"),
    ] {
        let message = post_image(
            &format!("/api/detect?{query}"),
            "image/png",
            example_photo(),
        )
        .error(400);
        assert!(message.contains(needle), "{query}: {message}");
    }
    // Over 25 MB.
    let big = vec![0u8; 26_000_000];
    let message = post_image("/api/detect", "image/png", &big).error(413);
    assert!(message.contains("25000000"), "{message}");
    // GET on a POST route.
    assert!(get("/api/detect").error(405).contains("POST"));
    assert_alive();
}
