//! Rooms (scenes of several photos) on the server (issue 40, defect 4): too many objects in
//! all the photos are refused at once, a room's fit stops at the request's time limit and when
//! its client goes away.

use std::io::Write;
use std::net::{SocketAddr, TcpStream};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use vpmap_metrology::synth::{RoomSynthOptions, VanishingPointForm, synthesize_room};
use vpmap_web::ServerLimits;

use crate::limits::start_server;
use crate::{post_json, request_to};

/// A room file of `photos` photos of a synthetic room of `boxes` boxes (1 px of click noise):
/// the room's four photos, repeated in turn beyond four.
pub(crate) fn room_json(photos: usize, boxes: usize, seed: u64) -> String {
    let (room, _) = synthesize_room(&RoomSynthOptions {
        seed,
        photos: photos.min(4),
        boxes,
        noise_px: 1.0,
        vanishing_points: VanishingPointForm::Lines,
        ..RoomSynthOptions::default()
    })
    .unwrap();
    let four: Vec<serde_json::Value> = room
        .photos()
        .map(|p| serde_json::to_value(p).unwrap())
        .collect();
    let all: Vec<&serde_json::Value> = four.iter().cycle().take(photos).collect();
    serde_json::json!({"version": 1, "photos": all}).to_string()
}

/// 16 photos of 49 to 60 objects each (892 in all, within the limit): 0.9 s of fitting in a
/// release build, about 15 s in a debug build.
fn slow_room() -> &'static str {
    static ROOM: OnceLock<String> = OnceLock::new();
    ROOM.get_or_init(|| room_json(16, 60, 6))
}

#[test]
fn a_room_of_too_many_objects_is_refused_at_once_naming_them() {
    // 4 photos of 300 objects: 1.4 s in a release build before the limit, refused after the
    // first photo's fit failed to converge.
    let room = room_json(4, 300, 2);
    let started = Instant::now();
    let message = post_json("/api/build", &room).error(400);
    let took = started.elapsed();
    assert!(
        message.contains("4 photos hold 1200 objects in all (300 + 300 + 300 + 300)")
            && message.contains("more than the 1000"),
        "{message}"
    );
    assert!(took < Duration::from_secs(2), "refused after {took:?}");
}

#[test]
fn a_room_build_is_stopped_by_its_time_limit() {
    // The default limits: 6 s for a build's room fit.
    let started = Instant::now();
    let reply = post_json("/api/build", slow_room());
    let took = started.elapsed();
    if reply.status != 200 {
        let message = reply.error(400);
        assert!(
            message.contains("the room fit of 16 photos and 892 objects stopped")
                || message.contains("the room map of 16 photos stopped"),
            "{message}"
        );
        assert!(message.contains("time limit of 6"), "{message}");
    }
    assert!(took < Duration::from_secs(12), "answered after {took:?}");
}

#[test]
fn a_plan_on_a_room_keeps_the_plan_time_limit() {
    let body = format!(
        r#"{{"scene": {}, "start": [0.0, 1.0], "goal": [0.5, 2.0], "planners": ["astar"]}}"#,
        slow_room()
    );
    let started = Instant::now();
    let reply = post_json("/api/plan", &body);
    let took = started.elapsed();
    if reply.status != 200 {
        let message = reply.error(400);
        assert!(
            !message.contains("stopped") || message.contains("time limit of 6"),
            "{message}"
        );
    }
    // 6 s from taking its slot, with slack for a loaded machine.
    assert!(took < Duration::from_secs(12), "answered after {took:?}");
}

/// One build slot, no waiting for it, and a build time limit of a minute.
fn patient_server() -> SocketAddr {
    static ADDR: OnceLock<SocketAddr> = OnceLock::new();
    *ADDR.get_or_init(|| {
        start_server(ServerLimits {
            build_slots: 1,
            slot_wait: Duration::ZERO,
            build_timeout: Duration::from_secs(60),
            ..ServerLimits::default()
        })
    })
}

/// Whether the build slot is free: a light build is answered 200, or 503 when busy.
fn build_slot_free(addr: SocketAddr) -> bool {
    let reply = request_to(
        addr,
        "POST",
        "/api/build?resolution=0.2",
        &[("Content-Type", "application/json")],
        crate::OFFICE.as_bytes(),
    );
    assert!(
        reply.status == 200 || reply.status == 503,
        "{}",
        reply.status
    );
    reply.status == 200
}

#[test]
fn a_room_build_whose_client_has_gone_stops_and_frees_its_slot() {
    let addr = patient_server();
    let body = slow_room();
    let mut stream = TcpStream::connect(addr).unwrap();
    write!(
        stream,
        "POST /api/build HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    std::thread::sleep(Duration::from_secs(2));
    assert!(!build_slot_free(addr), "the room build was not at work");
    drop(stream);
    let gone = Instant::now();
    while !build_slot_free(addr) {
        assert!(
            gone.elapsed() < Duration::from_secs(3),
            "the build slot is still taken {:?} after the client left",
            gone.elapsed()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The bundled room with photo 2's "box0" and "box1" named the other way round (issue 39's
/// swapped names): a room whose photos do not fit together.
pub(crate) fn room_with_swapped_names() -> serde_json::Value {
    let bundled = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/room.json");
    let mut room: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(bundled).unwrap()).unwrap();
    for o in room["photos"][1]["objects"].as_array_mut().unwrap() {
        let swapped = match o["name"].as_str().unwrap() {
            "box0" => "box1",
            "box1" => "box0",
            other => other,
        };
        o["name"] = serde_json::Value::String(swapped.to_owned());
    }
    room
}

/// What the library says about `room` (the text the CLI, the server and the Python module pass
/// on).
fn library_error(room: &serde_json::Value) -> String {
    let scene = vpmap_metrology::scene::Scene::from_json_str(&room.to_string()).unwrap();
    vpmap_metrology::map::build_map(&scene, &vpmap_metrology::map::BuildOptions::default())
        .err()
        .map_or_else(|| panic!("the library built the room"), |e| e.to_string())
}

/// A server with two minutes for a room's build and plan (a debug build's refusal fits every
/// start, and other tests share the two cores).
fn unhurried_server() -> SocketAddr {
    static ADDR: OnceLock<SocketAddr> = OnceLock::new();
    *ADDR.get_or_init(|| {
        start_server(ServerLimits {
            slot_wait: Duration::from_secs(120),
            build_timeout: Duration::from_secs(120),
            plan_timeout: Duration::from_secs(120),
            ..ServerLimits::default()
        })
    })
}

fn post_unhurried(target: &str, body: &str) -> crate::Reply {
    request_to(
        unhurried_server(),
        "POST",
        target,
        &[("Content-Type", "application/json")],
        body.as_bytes(),
    )
}

#[test]
fn an_inconsistent_room_is_refused_by_build_and_plan_with_the_library_s_words() {
    // Issue 39: the page, `/api/plan` on a room, the CLI and the Python module say the same
    // thing. Here: `/api/build` and `/api/plan` answer 400 with the library's message itself.
    let room = room_with_swapped_names();
    let want = library_error(&room);
    assert!(
        want.starts_with("the room's photos do not fit together")
            && want.contains("photo 2")
            && want.contains("\"box0\"")
            && want.contains("\"box1\""),
        "{want}"
    );
    let build = post_unhurried("/api/build", &room.to_string()).error(400);
    assert_eq!(build, format!("scene: {want}"));
    let plan = post_unhurried(
        "/api/plan",
        &serde_json::json!({
            "scene": room,
            "start": [0.0, 1.0],
            "goal": [1.0, 2.0],
        })
        .to_string(),
    )
    .error(400);
    assert_eq!(plan, build);
}

#[test]
fn a_room_build_takes_a_pinned_placement_and_refuses_a_bad_one_by_name() {
    let bundled = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/room.json");
    let mut room: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(bundled).unwrap()).unwrap();
    room["photos"][2]["placement_turn_deg"] = serde_json::json!(45);
    let e = post_unhurried("/api/build", &room.to_string()).error(400);
    assert!(
        e.contains("photos[2].placement_turn_deg") && e.contains("45 is not a quarter turn"),
        "{e}"
    );
    // The turn the fit chooses, pinned: the same map, which says it is pinned.
    room["photos"][2]
        .as_object_mut()
        .unwrap()
        .remove("placement_turn_deg");
    let free = post_unhurried("/api/build", &room.to_string());
    assert_eq!(free.status, 200);
    let free = free.json();
    let mut pinned_at = None;
    for turn in [0, 90, 180, 270] {
        room["photos"][2]["placement_turn_deg"] = serde_json::json!(turn);
        let reply = post_unhurried("/api/build", &room.to_string());
        if reply.status != 200 {
            continue;
        }
        let v = reply.json();
        let same = (0..3).all(|k| {
            (0..2).all(|i| {
                let at =
                    |m: &serde_json::Value| m["map"]["cameras"][k]["position"][i].as_f64().unwrap();
                (at(&v) - at(&free)).abs() < 1e-9
            })
        });
        if same {
            assert!(
                v["map"]["warnings"].as_array().unwrap().iter().any(|w| w
                    .as_str()
                    .unwrap()
                    .contains("photo 3's placement is pinned")),
                "{}",
                v["map"]["warnings"]
            );
            pinned_at = Some(turn);
        }
    }
    assert!(
        pinned_at.is_some(),
        "no pinned turn gives the fit's own map"
    );
    // Photo 3 is tied by several boxes: one turn fits, the others are refused or differ.
}
