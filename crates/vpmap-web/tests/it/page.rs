//! The page, the example, unknown paths and the request guard.

use crate::{OFFICE, assert_alive, base64_decode, get, post_json, request, server};

#[test]
fn index_and_assets_are_served_from_the_embedded_folder() {
    let index = get("/");
    assert_eq!(index.status, 200);
    assert_eq!(
        index.header("content-type"),
        Some("text/html; charset=utf-8")
    );
    assert_eq!(index.header("x-content-type-options"), Some("nosniff"));
    let same = get("/assets/index.html");
    assert_eq!(same.status, 200);
    assert_eq!(same.body, index.body);
    let on_disk = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/index.html")).unwrap();
    assert_eq!(index.body, on_disk);
}

#[test]
fn nothing_outside_the_assets_is_reachable() {
    for target in [
        "/assets/no-such-file.js",
        "/assets/../Cargo.toml",
        "/assets/%2e%2e/Cargo.toml",
        "/assets/..%2fCargo.toml",
        "/assets/%ff%fe",
        "/assets/",
        "/Cargo.toml",
        "/src/lib.rs",
        "/api/nothing",
    ] {
        let reply = get(target);
        assert!(
            reply.status == 404 || reply.status == 400,
            "{target}: {}",
            reply.status
        );
        assert!(!reply.error(reply.status).is_empty());
    }
    let message = get("/no/such/path").error(404);
    assert!(message.contains("/no/such/path"), "{message}");
    assert_alive();
}

#[test]
fn example_is_the_office_scene_with_a_photo_of_it() {
    let reply = get("/api/example");
    assert_eq!(reply.status, 200);
    let v = reply.json();
    let office: serde_json::Value = serde_json::from_str(OFFICE).unwrap();
    assert_eq!(v["scene"], office);
    assert_eq!(v["name"], "office");
    let png = base64_decode(v["photo_png_base64"].as_str().unwrap());
    let photo = image::load_from_memory_with_format(&png, image::ImageFormat::Png).unwrap();
    assert_eq!((photo.width(), photo.height()), (1600, 1200));
    assert_eq!(v["photo"]["width"], 1600);
    assert_eq!(v["photo"]["media_type"], "image/png");
    assert_eq!(v["truth"]["camera"]["pitch_deg"], 25.0);
    // The photo shows the annotated boxes: the crate's near top corner sits between the
    // crate's lit top and its front face, both unlike the floor tiles around.
    let rgb = photo.to_rgb8();
    let above = rgb.get_pixel(982, 880).0;
    let below = rgb.get_pixel(982, 900).0;
    assert_ne!(above, below, "no edge at the crate's near top corner");
    // POST is not how to get it.
    assert!(post_json("/api/example", "{}").error(405).contains("GET"));
}

#[test]
fn cross_origin_and_foreign_host_requests_are_refused() {
    let addr = server();
    let own = format!("http://{addr}");
    let reply = request(
        "POST",
        "/api/build",
        &[("Origin", own.as_str())],
        OFFICE.as_bytes(),
    );
    assert_eq!(reply.status, 200);
    let reply = request(
        "POST",
        "/api/build",
        &[("Origin", "http://evil.example")],
        OFFICE.as_bytes(),
    );
    assert!(reply.error(403).contains("evil.example"));
    let reply = request("GET", "/api/example", &[("Origin", "null")], b"");
    assert!(reply.error(403).contains("cross-origin"));
    assert_alive();
}

#[test]
fn foreign_host_names_are_refused_on_loopback() {
    // A raw request with its own Host header (DNS rebinding: evil.example resolving to
    // 127.0.0.1).
    use std::io::{Read, Write};
    let mut stream = std::net::TcpStream::connect(server()).unwrap();
    stream
        .write_all(b"GET / HTTP/1.1\r\nHost: evil.example:8080\r\nConnection: close\r\n\r\n")
        .unwrap();
    let mut raw = String::new();
    stream.read_to_string(&mut raw).unwrap();
    assert!(raw.starts_with("HTTP/1.1 403"), "{raw}");
    assert!(raw.contains("loopback"), "{raw}");
    let mut stream = std::net::TcpStream::connect(server()).unwrap();
    stream
        .write_all(b"GET / HTTP/1.1\r\nHost: localhost:8080\r\nConnection: close\r\n\r\n")
        .unwrap();
    let mut raw = String::new();
    stream.read_to_string(&mut raw).unwrap();
    assert!(raw.starts_with("HTTP/1.1 200"), "{}", &raw[..100]);
}
