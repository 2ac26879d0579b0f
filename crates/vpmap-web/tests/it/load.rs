//! A bounded load test: bursts of concurrent build, plan and detect requests against a
//! server in its own process (this test binary run again as `load::server_process`, so that
//! its memory is the server's alone), on loopback only.
//!
//! `bursts_keep_the_server_up_quick_and_small` runs with the other tests (48
//! requests); `throughput` is ignored and prints the latency and throughput table of
//! `docs/web-api.md`:
//!
//!     cargo test --release -p vpmap-web --test it -- --ignored --nocapture load::throughput

use std::io::{BufRead, BufReader, Read};
use std::net::SocketAddr;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use serde_json::json;

use crate::{OFFICE, request_to};

/// Set in the environment of the server process.
const CHILD_ENV: &str = "VPMAP_WEB_LOAD_SERVER";
/// The line the server process prints its address on.
const ADDR_LINE: &str = "vpmap-load-server ";

/// The longest any answer may take in the load test (debug build, several clients, a loaded
/// 2-core machine): a busy endpoint answers 503 after its 2 s wait for a slot, and the
/// heaviest request of the mix (detection of a 1600 x 1200 photo) takes about 1 s in a debug build.
const MAX_LATENCY: Duration = Duration::from_secs(10);
/// How far the server's resident memory may stay above its baseline after the bursts. (glibc
/// kept 23 MiB or more before `return_freed_memory_promptly`; see `src/memory.rs`.)
const RSS_MARGIN_KIB: u64 = 8 * 1024;

/// The server of the load tests: this test binary, run for this test only. Serves on
/// 127.0.0.1 until its standard input closes.
#[test]
#[ignore = "the server process of the load tests, started by them"]
fn server_process() {
    if std::env::var_os(CHILD_ENV).is_none() {
        return;
    }
    // As `vpmap serve` (`serve_until_ctrl_c`) does.
    assert!(vpmap_web::return_freed_memory_promptly());
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .max_blocking_threads(16)
        .build()
        .unwrap();
    runtime.spawn(async {
        let server = vpmap_web::Server::bind(
            "127.0.0.1:0".parse().unwrap(),
            vpmap_web::ServeOptions::default(),
        )
        .await
        .unwrap();
        println!("\n{ADDR_LINE}{}", server.local_addr());
        server.serve(std::future::pending()).await.unwrap();
    });
    // Until the test that started this process drops its end of the pipe (or dies).
    let mut rest = Vec::new();
    let _ = std::io::stdin().read_to_end(&mut rest);
    runtime.shutdown_timeout(Duration::from_secs(1));
}

/// The server process; killed when dropped.
pub(crate) struct ServerProcess {
    child: std::process::Child,
    pub(crate) addr: SocketAddr,
}

impl ServerProcess {
    pub(crate) fn start() -> Self {
        let mut child = Command::new(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "load::server_process",
                "--ignored",
                "--nocapture",
                "--test-threads=1",
            ])
            .env(CHILD_ENV, "1")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let stdout = child.stdout.take().unwrap();
        let mut lines = BufReader::new(stdout).lines();
        let addr = loop {
            let line = lines
                .next()
                .expect("the server process ended without an address")
                .unwrap();
            // The test harness may have written `test load::server_process ... ` first.
            if let Some((_, addr)) = line.split_once(ADDR_LINE) {
                break addr.trim().parse().unwrap();
            }
        };
        // Keep reading what it prints, so that it never blocks on a full pipe.
        std::thread::spawn(move || lines.for_each(drop));
        Self { child, addr }
    }

    pub(crate) fn pid(&self) -> u32 {
        self.child.id()
    }

    pub(crate) fn running(&mut self) -> bool {
        self.child.try_wait().unwrap().is_none()
    }
}

impl Drop for ServerProcess {
    fn drop(&mut self) {
        drop(self.child.stdin.take());
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Resident memory of process `pid` (VmRSS), KiB.
pub(crate) fn rss_kib(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap()
}

/// Samples a process's resident memory every 20 ms and keeps the largest.
pub(crate) struct PeakRss {
    stop: Arc<AtomicBool>,
    peak: Arc<AtomicU64>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl PeakRss {
    pub(crate) fn start(pid: u32) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let peak = Arc::new(AtomicU64::new(0));
        let (s, p) = (Arc::clone(&stop), Arc::clone(&peak));
        let thread = std::thread::spawn(move || {
            while !s.load(Ordering::Relaxed) {
                p.fetch_max(rss_kib(pid), Ordering::Relaxed);
                std::thread::sleep(Duration::from_millis(20));
            }
        });
        Self {
            stop,
            peak,
            thread: Some(thread),
        }
    }

    pub(crate) fn finish(mut self) -> u64 {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            t.join().unwrap();
        }
        self.peak.load(Ordering::Relaxed)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Build,
    Plan,
    Detect,
    /// A build at 1 cm: 0.9 million cells.
    BuildFine,
    /// Theta* on the office at 5 mm (3.7 million cells): stopped by its sight budget or
    /// time limit (400), after about a second in a release build.
    PlanHeavy,
}

impl Kind {
    const ALL: [Kind; 4] = [Kind::Build, Kind::Plan, Kind::Detect, Kind::BuildFine];

    fn name(self) -> &'static str {
        match self {
            Kind::Build => "build",
            Kind::Plan => "plan",
            Kind::Detect => "detect",
            Kind::BuildFine => "build at 1 cm",
            Kind::PlanHeavy => "plan at 5 mm (Theta*, stopped)",
        }
    }

    /// Target, Content-Type and body of the request: the office example at the page's
    /// default resolution, a plan across it with the default planners, its photo.
    fn request(self) -> (&'static str, &'static str, &'static [u8]) {
        static PLAN: OnceLock<Vec<u8>> = OnceLock::new();
        static PHOTO: OnceLock<Vec<u8>> = OnceLock::new();
        static HEAVY: OnceLock<Vec<u8>> = OnceLock::new();
        match self {
            Kind::Build => ("/api/build", "application/json", OFFICE.as_bytes()),
            Kind::BuildFine => (
                "/api/build?resolution=0.01",
                "application/json",
                OFFICE.as_bytes(),
            ),
            Kind::Plan => (
                "/api/plan",
                "application/json",
                PLAN.get_or_init(|| {
                    json!({
                        "scene": serde_json::from_str::<serde_json::Value>(OFFICE).unwrap(),
                        "start": [-1.5, 2.0],
                        "goal": [2.0, 7.5],
                    })
                    .to_string()
                    .into_bytes()
                }),
            ),
            Kind::PlanHeavy => (
                "/api/plan",
                "application/json",
                HEAVY.get_or_init(|| {
                    json!({
                        "scene": serde_json::from_str::<serde_json::Value>(OFFICE).unwrap(),
                        "resolution": 0.005,
                        "start": [-1.5, 2.0],
                        "goal": [2.0, 7.5],
                        "planners": ["theta-star"],
                    })
                    .to_string()
                    .into_bytes()
                }),
            ),
            Kind::Detect => (
                "/api/detect",
                "image/png",
                PHOTO.get_or_init(|| vpmap_web::example::office_photo_png().unwrap().0),
            ),
        }
    }
}

#[derive(Debug)]
struct Sample {
    kind: Kind,
    status: u16,
    latency: Duration,
    retry_after: bool,
}

fn send(addr: SocketAddr, kind: Kind) -> Sample {
    let (target, content_type, body) = kind.request();
    let started = Instant::now();
    let reply = request_to(
        addr,
        "POST",
        target,
        &[("Content-Type", content_type)],
        body,
    );
    Sample {
        kind,
        status: reply.status,
        latency: started.elapsed(),
        retry_after: reply.header("retry-after").is_some(),
    }
}

/// `clients` clients at once, each sending `kinds` in turn (client `i` starting at
/// `kinds[i % len]`), `per_client` requests each.
fn burst(addr: SocketAddr, clients: usize, per_client: usize, kinds: &[Kind]) -> Vec<Sample> {
    let kinds = kinds.to_vec();
    let threads: Vec<_> = (0..clients)
        .map(|i| {
            let kinds = kinds.clone();
            std::thread::spawn(move || {
                (0..per_client)
                    .map(|j| send(addr, kinds[(i + j) % kinds.len()]))
                    .collect::<Vec<_>>()
            })
        })
        .collect();
    threads
        .into_iter()
        .flat_map(|t| t.join().unwrap())
        .collect()
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

#[test]
fn bursts_keep_the_server_up_quick_and_small() {
    let mut server = ServerProcess::start();
    let addr = server.addr;
    // Warm up: the worker threads, the allocator's arenas, the example's cache.
    let warm = burst(addr, 6, 2, &Kind::ALL);
    assert!(warm.iter().all(|s| s.status == 200 || s.status == 503));
    std::thread::sleep(Duration::from_millis(500));
    let baseline = rss_kib(server.pid());
    let peak = PeakRss::start(server.pid());
    let started = Instant::now();
    let mut samples = Vec::new();
    for _ in 0..3 {
        samples.extend(burst(addr, 6, 2, &Kind::ALL));
        assert!(server.running(), "the server process died");
    }
    let took = started.elapsed();
    let peak = peak.finish();
    std::thread::sleep(Duration::from_millis(500));
    let after = rss_kib(server.pid());
    eprintln!(
        "load: {} requests in {took:.1?}; RSS baseline {} MiB, peak {} MiB, after {} MiB",
        samples.len(),
        baseline / 1024,
        peak / 1024,
        after / 1024
    );
    for kind in Kind::ALL {
        let of: Vec<&Sample> = samples.iter().filter(|s| s.kind == kind).collect();
        let ok = of.iter().filter(|s| s.status == 200).count();
        let slowest = of.iter().map(|s| s.latency).max().unwrap();
        eprintln!(
            "load: {}: {} requests, {ok} answered 200, the rest 503; slowest {slowest:.2?}",
            kind.name(),
            of.len()
        );
        assert!(ok > 0, "no {} request succeeded", kind.name());
    }
    for s in &samples {
        assert!(
            s.status == 200 || (s.status == 503 && s.retry_after),
            "{s:?}"
        );
        assert!(s.latency <= MAX_LATENCY, "{s:?}");
    }
    assert!(server.running(), "the server process died");
    // The bursts did take memory, so its return means something.
    assert!(
        peak >= baseline + 2 * RSS_MARGIN_KIB,
        "peak {peak} KiB, baseline {baseline} KiB"
    );
    assert!(
        after <= baseline + RSS_MARGIN_KIB,
        "resident memory {} MiB after the bursts, baseline {} MiB (margin {} MiB)",
        after / 1024,
        baseline / 1024,
        RSS_MARGIN_KIB / 1024
    );
}

#[test]
#[ignore = "a measurement (release build): prints the table of docs/web-api.md"]
fn throughput() {
    let mut server = ServerProcess::start();
    let addr = server.addr;
    let _ = burst(addr, 2, 2, &Kind::ALL);
    let baseline = rss_kib(server.pid());
    println!(
        "{} cores, load average before: {}",
        std::thread::available_parallelism().map_or(0, std::num::NonZero::get),
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    println!(
        "| requests of | clients | requests | answered (200/400) | 503 | p50 | p95 | max | answers/s | peak RSS |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let runs: [(&[Kind], usize, usize); 9] = [
        (&[Kind::Build], 4, 50),
        (&[Kind::Plan], 2, 50),
        (&[Kind::Detect], 2, 10),
        (&[Kind::BuildFine], 4, 5),
        (&[Kind::Build], 16, 10),
        (&[Kind::Plan], 8, 10),
        (&[Kind::Detect], 8, 3),
        (&[Kind::PlanHeavy], 8, 1),
        (&Kind::ALL, 12, 6),
    ];
    for (kinds, clients, per_client) in runs {
        let name = kinds
            .iter()
            .map(|k| k.name())
            .collect::<Vec<_>>()
            .join(" + ");
        let peak = PeakRss::start(server.pid());
        let started = Instant::now();
        let samples = burst(addr, clients, per_client, kinds);
        let took = started.elapsed();
        let peak = peak.finish();
        let ok = samples
            .iter()
            .filter(|s| s.status == 200 || s.status == 400)
            .count();
        let busy = samples.iter().filter(|s| s.status == 503).count();
        let mut latencies: Vec<Duration> = samples.iter().map(|s| s.latency).collect();
        latencies.sort();
        let ms = |d: Duration| format!("{:.0} ms", d.as_secs_f64() * 1e3);
        println!(
            "| {name} | {clients} | {} | {ok} | {busy} | {} | {} | {} | {:.1} | {} MiB |",
            samples.len(),
            ms(percentile(&latencies, 0.5)),
            ms(percentile(&latencies, 0.95)),
            ms(*latencies.last().unwrap()),
            samples.len() as f64 / took.as_secs_f64(),
            peak / 1024
        );
        assert!(server.running());
    }
    std::thread::sleep(Duration::from_millis(500));
    println!(
        "RSS: {} MiB after warm-up, {} MiB after the runs",
        baseline / 1024,
        rss_kib(server.pid()) / 1024
    );
}
