//! The web API over real HTTP: one server on 127.0.0.1:0, started in-process for the whole
//! test binary, and a minimal HTTP/1.1 client on `std::net::TcpStream`, so that the tests see
//! exactly the bytes a browser would get.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

mod build;
mod detect;
mod fuzz_regressions;
mod limits;
mod load;
mod page;
mod photos;
mod plan;
mod rooms;
mod smooth;

use std::fmt::Write as _;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Duration;

use base64::Engine as _;

/// The bundled example scene.
pub(crate) const OFFICE: &str = include_str!("../../../../examples/office.json");

/// Lines the server logged (internal errors).
pub(crate) fn logged() -> Vec<String> {
    log_lines().lock().map(|l| l.clone()).unwrap_or_default()
}

fn log_lines() -> &'static Arc<Mutex<Vec<String>>> {
    static LINES: OnceLock<Arc<Mutex<Vec<String>>>> = OnceLock::new();
    LINES.get_or_init(|| Arc::new(Mutex::new(Vec::new())))
}

/// The test server's address (started on first use, on a free port).
pub(crate) fn server() -> SocketAddr {
    static ADDR: OnceLock<SocketAddr> = OnceLock::new();
    *ADDR.get_or_init(|| {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let runtime = tokio::runtime::Builder::new_multi_thread()
                .worker_threads(2)
                .enable_all()
                .build()
                .unwrap();
            runtime.block_on(async move {
                let lines = Arc::clone(log_lines());
                let options = vpmap_web::ServeOptions {
                    log: Some(Arc::new(move |line: &str| {
                        if let Ok(mut l) = lines.lock() {
                            l.push(line.to_owned());
                        }
                    })),
                };
                let server = vpmap_web::Server::bind("127.0.0.1:0".parse().unwrap(), options)
                    .await
                    .unwrap();
                tx.send(server.local_addr()).unwrap();
                server.serve(std::future::pending()).await.unwrap();
            });
        });
        rx.recv_timeout(Duration::from_secs(30)).unwrap()
    })
}

/// An HTTP answer.
#[derive(Debug)]
pub(crate) struct Reply {
    pub(crate) status: u16,
    pub(crate) headers: Vec<(String, String)>,
    pub(crate) body: Vec<u8>,
}

impl Reply {
    pub(crate) fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }

    pub(crate) fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body).unwrap_or_else(|e| {
            panic!(
                "status {}: body is not JSON ({e}): {}",
                self.status,
                String::from_utf8_lossy(&self.body[..self.body.len().min(500)])
            )
        })
    }

    /// The `error` message of a JSON error answer with `status`.
    pub(crate) fn error(&self, status: u16) -> String {
        assert_eq!(
            self.status,
            status,
            "{}",
            String::from_utf8_lossy(&self.body[..self.body.len().min(500)])
        );
        assert_eq!(self.header("content-type"), Some("application/json"));
        let message = self.json()["error"].as_str().unwrap().to_owned();
        assert!(
            !message.is_empty() && !message.contains('\n'),
            "{message:?}"
        );
        message
    }
}

/// Send one request (`Connection: close`) and read the whole answer. The body is written on
/// another thread, so that an answer sent before the body is read (413) is still received.
pub(crate) fn request(method: &str, target: &str, headers: &[(&str, &str)], body: &[u8]) -> Reply {
    request_to(server(), method, target, headers, body)
}

/// [`request`] to the server at `addr`.
pub(crate) fn request_to(
    addr: SocketAddr,
    method: &str,
    target: &str,
    headers: &[(&str, &str)],
    body: &[u8],
) -> Reply {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(120)))
        .unwrap();
    let mut head = format!(
        "{method} {target} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\nContent-Length: {}\r\n",
        body.len()
    );
    for (k, v) in headers {
        let _ = write!(head, "{k}: {v}\r\n");
    }
    head.push_str("\r\n");
    stream.write_all(head.as_bytes()).unwrap();
    let mut writer = stream.try_clone().unwrap();
    let body = body.to_vec();
    let sender = std::thread::spawn(move || {
        // The server may answer and close before reading everything (413).
        let _ = writer.write_all(&body);
    });
    let mut raw = Vec::new();
    let mut buf = [0u8; 16384];
    loop {
        match stream.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => raw.extend_from_slice(&buf[..n]),
            // A reset after the answer (the server closed with the body unread).
            Err(_) if !raw.is_empty() => break,
            Err(e) => panic!("reading the answer to {method} {target}: {e}"),
        }
    }
    let _ = sender.join();
    parse_reply(&raw)
}

pub(crate) fn parse_reply(raw: &[u8]) -> Reply {
    let split = raw
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("no end of headers");
    let head = String::from_utf8_lossy(&raw[..split]).into_owned();
    let mut lines = head.split("\r\n");
    let status: u16 = lines
        .next()
        .and_then(|l| l.split(' ').nth(1))
        .and_then(|s| s.parse().ok())
        .expect("no status");
    let headers: Vec<(String, String)> = lines
        .filter_map(|l| l.split_once(':'))
        .map(|(k, v)| (k.trim().to_ascii_lowercase(), v.trim().to_owned()))
        .collect();
    let mut body = raw[split + 4..].to_vec();
    if headers
        .iter()
        .any(|(k, v)| k == "transfer-encoding" && v.contains("chunked"))
    {
        body = dechunk(&body);
    }
    Reply {
        status,
        headers,
        body,
    }
}

fn dechunk(mut data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let line_end = data.windows(2).position(|w| w == b"\r\n").unwrap();
        let size = usize::from_str_radix(
            String::from_utf8_lossy(&data[..line_end])
                .split(';')
                .next()
                .unwrap()
                .trim(),
            16,
        )
        .unwrap();
        data = &data[line_end + 2..];
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&data[..size]);
        data = &data[size + 2..];
    }
}

pub(crate) fn get(target: &str) -> Reply {
    request("GET", target, &[], b"")
}

pub(crate) fn post_json(target: &str, body: &str) -> Reply {
    request(
        "POST",
        target,
        &[("Content-Type", "application/json")],
        body.as_bytes(),
    )
}

/// The server still answers (after a bad request).
pub(crate) fn assert_alive() {
    let reply = get("/assets/index.html");
    assert_eq!(reply.status, 200);
    let reply = post_json("/api/build?resolution=0.2", OFFICE);
    assert_eq!(
        reply.status,
        200,
        "{}",
        String::from_utf8_lossy(&reply.body)
    );
}

pub(crate) fn base64_decode(text: &str) -> Vec<u8> {
    base64::engine::general_purpose::STANDARD
        .decode(text)
        .unwrap()
}

#[test]
fn internal_errors_are_never_logged_by_these_tests() {
    // Every bad request of the other tests is a 4xx, never a bug; run them first.
    build::malformed_and_refused_scenes_are_400_with_a_message();
    plan::bad_plan_requests_are_400_with_a_message();
    assert!(logged().is_empty(), "{:?}", logged());
}
