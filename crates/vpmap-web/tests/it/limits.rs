//! The server's limits on time, size and concurrency: slow clients are dropped, oversized
//! declared bodies are refused before they are read, and a busy endpoint answers 503.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use vpmap_web::ServerLimits;

use crate::{OFFICE, parse_reply, request_to, server};

/// Timeouts of the strict server, short so that the tests are quick.
const HEADER_TIMEOUT: Duration = Duration::from_secs(1);
const BODY_TIMEOUT: Duration = Duration::from_secs(2);
/// What the server may take beyond a timeout to act on it (a loaded 2-core machine).
const SLACK: Duration = Duration::from_millis(1500);

/// A second server with short timeouts, one build and one plan at a time and no waiting
/// for a slot.
fn strict_server() -> SocketAddr {
    static ADDR: OnceLock<SocketAddr> = OnceLock::new();
    *ADDR.get_or_init(|| {
        start_server(ServerLimits {
            header_read_timeout: HEADER_TIMEOUT,
            body_read_timeout: BODY_TIMEOUT,
            build_slots: 1,
            plan_slots: 1,
            detect_slots: 1,
            slot_wait: Duration::ZERO,
            planner_timeout: Duration::from_secs(60),
            plan_timeout: Duration::from_secs(60),
            ..ServerLimits::default()
        })
    })
}

/// Start a server with `limits` on its own runtime, in this process.
pub(crate) fn start_server(limits: ServerLimits) -> SocketAddr {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()
            .unwrap();
        runtime.block_on(async move {
            let server = vpmap_web::Server::bind(
                "127.0.0.1:0".parse().unwrap(),
                vpmap_web::ServeOptions::default(),
            )
            .await
            .unwrap()
            .with_limits(limits);
            tx.send(server.local_addr()).unwrap();
            server.serve(std::future::pending()).await.unwrap();
        });
    });
    rx.recv_timeout(Duration::from_secs(30)).unwrap()
}

/// Read until the server closes the connection (or resets it), at most `within`. Returns
/// what was read and when the connection ended, or `None` if it was still open.
fn read_until_closed(stream: &mut TcpStream, within: Duration) -> (Vec<u8>, Option<Duration>) {
    let started = Instant::now();
    let mut raw = Vec::new();
    let mut buf = [0u8; 16384];
    loop {
        let left = within.saturating_sub(started.elapsed());
        if left.is_zero() {
            return (raw, None);
        }
        stream.set_read_timeout(Some(left)).unwrap();
        match stream.read(&mut buf) {
            Ok(0) => return (raw, Some(started.elapsed())),
            Ok(n) => raw.extend_from_slice(&buf[..n]),
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                return (raw, None);
            }
            // Reset by the server: closed.
            Err(_) => return (raw, Some(started.elapsed())),
        }
    }
}

/// Write `bytes` one at a time, `every` apart, until the server closes the connection.
fn trickle(stream: &TcpStream, bytes: Vec<u8>, every: Duration) -> std::thread::JoinHandle<()> {
    let mut writer = stream.try_clone().unwrap();
    std::thread::spawn(move || {
        for b in bytes {
            if writer.write_all(&[b]).is_err() {
                return;
            }
            std::thread::sleep(every);
        }
    })
}

fn head(addr: SocketAddr, target: &str, content_length: u64) -> String {
    format!(
        "POST {target} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {content_length}\r\n\r\n"
    )
}

#[test]
fn declared_10_gb_body_is_refused_with_413_before_it_is_sent() {
    let addr = server();
    for (target, declared, limit) in [
        ("/api/plan", 10_000_000_000_u64, "4194304"),
        ("/api/build", 10_000_000_000, "4194304"),
        ("/api/detect", 25_000_001, "25000000"),
    ] {
        let mut stream = TcpStream::connect(addr).unwrap();
        let started = Instant::now();
        // Headers only: not one byte of the body is sent.
        stream
            .write_all(head(addr, target, declared).as_bytes())
            .unwrap();
        let (raw, closed) = read_until_closed(&mut stream, Duration::from_secs(10));
        let reply = parse_reply(&raw);
        let message = reply.error(413);
        assert!(
            message.contains(&declared.to_string()) && message.contains(limit),
            "{message}"
        );
        assert_eq!(reply.header("connection"), Some("close"));
        // Answered and closed at once, not after waiting for the body.
        let closed = closed.unwrap_or_else(|| panic!("{target}: the connection was held"));
        assert!(closed < Duration::from_secs(2), "{target}: {closed:?}");
        assert!(started.elapsed() < Duration::from_secs(3));
    }
}

#[test]
fn chunked_body_beyond_the_limit_is_refused_with_413() {
    let addr = server();
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .write_all(
            format!(
                "POST /api/build HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n"
            )
            .as_bytes(),
        )
        .unwrap();
    let mut writer = stream.try_clone().unwrap();
    // 6 chunks of 1 MiB: over the 4 MiB limit, no declared length.
    let sender = std::thread::spawn(move || {
        let chunk = vec![b' '; 1 << 20];
        for _ in 0..6 {
            let ok = writer
                .write_all(format!("{:x}\r\n", chunk.len()).as_bytes())
                .and_then(|()| writer.write_all(&chunk))
                .and_then(|()| writer.write_all(b"\r\n"));
            if ok.is_err() {
                return;
            }
        }
        let _ = writer.write_all(b"0\r\n\r\n");
    });
    let (raw, closed) = read_until_closed(&mut stream, Duration::from_secs(20));
    let message = parse_reply(&raw).error(413);
    assert!(message.contains("4194304"), "{message}");
    assert!(closed.is_some());
    let _ = sender.join();
}

#[test]
fn slow_headers_are_dropped_after_the_header_timeout() {
    let addr = strict_server();
    // Ten clients sending their headers a byte every 100 ms (slow loris), and one that sends
    // nothing at all.
    let mut clients = Vec::new();
    for _ in 0..10 {
        let stream = TcpStream::connect(addr).unwrap();
        let writer = trickle(
            &stream,
            head(addr, "/api/build", 2).into_bytes(),
            Duration::from_millis(100),
        );
        clients.push((stream, Some(writer)));
    }
    clients.push((TcpStream::connect(addr).unwrap(), None));
    let started = Instant::now();
    for (mut stream, writer) in clients {
        let (raw, _) = read_until_closed(&mut stream, HEADER_TIMEOUT + SLACK * 2);
        let closed = started.elapsed();
        assert!(
            raw.is_empty(),
            "answered: {}",
            String::from_utf8_lossy(&raw)
        );
        assert!(
            closed >= HEADER_TIMEOUT.saturating_sub(Duration::from_millis(100))
                && closed <= HEADER_TIMEOUT + SLACK,
            "closed after {closed:?}; header timeout {HEADER_TIMEOUT:?}"
        );
        if let Some(writer) = writer {
            writer.join().unwrap();
        }
    }
    // Still serving.
    let reply = request_to(addr, "GET", "/assets/index.html", &[], b"");
    assert_eq!(reply.status, 200);
}

#[test]
fn slow_body_is_answered_408_after_the_body_timeout() {
    let addr = strict_server();
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .write_all(head(addr, "/api/plan", 1000).as_bytes())
        .unwrap();
    let started = Instant::now();
    let writer = trickle(&stream, vec![b' '; 1000], Duration::from_millis(100));
    let (raw, closed) = read_until_closed(&mut stream, BODY_TIMEOUT + SLACK * 2);
    let elapsed = started.elapsed();
    let message = parse_reply(&raw).error(408);
    assert!(
        message.contains("within 2 s") && message.contains("of 1000"),
        "{message}"
    );
    assert!(closed.is_some(), "the connection was held");
    assert!(
        elapsed >= BODY_TIMEOUT.saturating_sub(Duration::from_millis(100))
            && elapsed <= BODY_TIMEOUT + SLACK,
        "{elapsed:?}"
    );
    writer.join().unwrap();
}

#[test]
fn a_busy_endpoint_answers_503_with_retry_after() {
    let addr = strict_server();
    // A heavy build (3.7 million cells) holds the only build slot...
    let heavy = std::thread::spawn(move || {
        let started = Instant::now();
        let reply = request_to(
            addr,
            "POST",
            "/api/build?resolution=0.005",
            &[("Content-Type", "application/json")],
            OFFICE.as_bytes(),
        );
        (reply, started.elapsed())
    });
    std::thread::sleep(Duration::from_millis(300));
    // ...so a light one is told at once to come back.
    let started = Instant::now();
    let busy = request_to(
        addr,
        "POST",
        "/api/build?resolution=0.2",
        &[("Content-Type", "application/json")],
        OFFICE.as_bytes(),
    );
    let answered = started.elapsed();
    let (reply, heavy_took) = heavy.join().unwrap();
    assert_eq!(
        reply.status,
        200,
        "{}",
        String::from_utf8_lossy(&reply.body)
    );
    assert!(
        heavy_took > Duration::from_millis(600),
        "the heavy build took only {heavy_took:?}: too quick to test the slot"
    );
    let message = busy.error(503);
    assert!(
        message.contains("busy") && message.contains("/api/build"),
        "{message}"
    );
    assert_eq!(busy.header("retry-after"), Some("1"));
    assert!(answered < heavy_took, "{answered:?}");
    // Other endpoints have their own slots; and the freed slot is taken again.
    let reply = request_to(
        addr,
        "POST",
        "/api/build?resolution=0.2",
        &[("Content-Type", "application/json")],
        OFFICE.as_bytes(),
    );
    assert_eq!(reply.status, 200);
}

/// A plan request on the office at 5 mm (3.7 million cells) with the slow grid planners.
fn heavy_plan() -> String {
    serde_json::json!({
        "scene": serde_json::from_str::<serde_json::Value>(OFFICE).unwrap(),
        "resolution": 0.005,
        "start": [-1.5, 2.0],
        "goal": [2.0, 7.5],
        "planners": ["theta-star", "astar", "astar-ps"],
    })
    .to_string()
}

#[test]
fn a_plan_whose_client_has_gone_stops_and_frees_its_slot() {
    let addr = strict_server();
    let light = serde_json::json!({
        "scene": serde_json::from_str::<serde_json::Value>(OFFICE).unwrap(),
        "resolution": 0.2,
        "start": [-1.5, 2.0],
        "goal": [2.0, 7.5],
        "planners": ["astar"],
    })
    .to_string();
    let post = |body: &str| {
        request_to(
            addr,
            "POST",
            "/api/plan",
            &[("Content-Type", "application/json")],
            body.as_bytes(),
        )
    };
    // Uncancelled, the heavy plan runs for about 30 s in a debug build (until Theta*'s
    // sight budget), holding the only plan slot.
    let body = heavy_plan();
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .write_all(head(addr, "/api/plan", body.len() as u64).as_bytes())
        .unwrap();
    stream.write_all(body.as_bytes()).unwrap();
    // Planning is under way (rasterising takes about a second): the slot is taken.
    let started = Instant::now();
    loop {
        std::thread::sleep(Duration::from_millis(200));
        let reply = post(&light);
        assert!(
            reply.status == 503,
            "{}",
            String::from_utf8_lossy(&reply.body)
        );
        if started.elapsed() > Duration::from_millis(2500) {
            break;
        }
    }
    // The client goes away; the planners notice and the slot frees.
    drop(stream);
    let gone = Instant::now();
    loop {
        std::thread::sleep(Duration::from_millis(100));
        let reply = post(&light);
        if reply.status == 200 {
            break;
        }
        assert_eq!(reply.status, 503);
        assert!(
            gone.elapsed() < Duration::from_secs(5),
            "the plan slot is still taken {:?} after the client left",
            gone.elapsed()
        );
    }
}

#[test]
fn a_plan_that_runs_too_long_is_stopped_by_its_time_limit() {
    // The default limits: 3 s for each planner. Uncancelled, Theta* alone runs for about
    // 30 s in a debug build on this grid.
    let started = Instant::now();
    let reply = crate::post_json("/api/plan", &heavy_plan());
    let took = started.elapsed();
    let message = reply.error(400);
    assert!(
        message.starts_with("theta-star: Theta* stopped"),
        "{message}"
    );
    // Its own 3 s, or less when rasterising took much of the request's 6 s; a release build
    // may use up the sight budget (about a second of work) first.
    let allowed_s = message
        .split_once("time limit of ")
        .and_then(|(_, rest)| rest.split(' ').next())
        .and_then(|s| s.parse::<f64>().ok());
    assert!(
        allowed_s.is_some_and(|s| s <= 3.0) || message.contains("max_sight_cells"),
        "{message}"
    );
    // At most the request's 6 s from taking its slot, with slack for a loaded machine.
    assert!(took < Duration::from_secs(10), "{took:?}");
}

#[test]
fn connections_beyond_the_cap_wait_until_one_closes() {
    const MAX_CONNECTIONS: usize = 4;
    let addr = start_server(ServerLimits {
        header_read_timeout: HEADER_TIMEOUT,
        max_connections: MAX_CONNECTIONS,
        ..ServerLimits::default()
    });
    // Every slot held by an idle connection, which the header timeout closes after 1 s.
    let idle: Vec<TcpStream> = (0..MAX_CONNECTIONS)
        .map(|_| TcpStream::connect(addr).unwrap())
        .collect();
    std::thread::sleep(Duration::from_millis(200));
    let started = Instant::now();
    let reply = request_to(addr, "GET", "/assets/index.html", &[], b"");
    let waited = started.elapsed();
    assert_eq!(reply.status, 200);
    // Accepted only once the idle connections had timed out.
    assert!(
        waited >= HEADER_TIMEOUT.saturating_sub(Duration::from_millis(400)),
        "answered after {waited:?}, before the idle connections were closed"
    );
    assert!(waited <= HEADER_TIMEOUT * 2 + SLACK, "{waited:?}");
    drop(idle);
}
