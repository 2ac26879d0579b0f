//! The server's limits on time and concurrency ([`ServerLimits`]), and the slots that cap
//! how many heavy requests of one endpoint are worked on at once.

use std::sync::Arc;
use std::time::Duration;

use axum::http::StatusCode;
use tokio::sync::{OwnedSemaphorePermit, Semaphore};

use crate::error::ApiError;

/// How long the server waits for clients and how much heavy work it takes on at once.
/// Every value is documented in `docs/web-api.md`; [`Default`] is what `vpmap serve` uses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ServerLimits {
    /// A request's line and headers must arrive within this after the connection opens or
    /// the previous answer is sent; otherwise the connection is closed without an answer.
    /// Also how long an idle keep-alive connection is kept.
    pub header_read_timeout: Duration,
    /// Most connections open at once; beyond it the server accepts no more until one
    /// closes (they wait in the system's backlog).
    pub max_connections: usize,
    /// A request's whole body must arrive within this after its headers; otherwise it is
    /// answered with 408 and the connection is closed.
    pub body_read_timeout: Duration,
    /// Most `/api/build` requests worked on at once.
    pub build_slots: usize,
    /// Most `/api/plan` requests worked on at once.
    pub plan_slots: usize,
    /// Most `/api/detect` requests (photos decoded and analysed) worked on at once.
    pub detect_slots: usize,
    /// How long a heavy request waits for a free slot before it is answered with 503.
    pub slot_wait: Duration,
    /// Time allowed to each planner of a `/api/plan` request; a planner still running then
    /// stops, and the request is answered with 400 naming it.
    pub planner_timeout: Duration,
    /// Time allowed to one `/api/plan` request from when it takes its slot: building its
    /// grid, then its planners (a planner starting late gets only what is left). A room's fit
    /// (a scene of several photos) counts in it too.
    pub plan_timeout: Duration,
    /// Time allowed to the fit of a photo or a room (a scene of several photos) in one
    /// `/api/build` request, from when it takes its slot; beyond it the request is answered
    /// with 400.
    pub build_timeout: Duration,
    /// Time allowed to the search for box proposals of one `/api/propose` request, from when
    /// it takes its slot (finding the photo's segments, on first use, counts in it but is
    /// not interrupted); beyond it the request is answered with 400.
    pub propose_timeout: Duration,
}

impl Default for ServerLimits {
    fn default() -> Self {
        Self {
            header_read_timeout: Duration::from_secs(10),
            max_connections: 256,
            body_read_timeout: Duration::from_secs(30),
            build_slots: 4,
            plan_slots: 2,
            detect_slots: 2,
            slot_wait: Duration::from_secs(2),
            planner_timeout: Duration::from_secs(3),
            plan_timeout: Duration::from_secs(6),
            build_timeout: Duration::from_secs(6),
            propose_timeout: Duration::from_secs(3),
        }
    }
}

/// `Retry-After` of a busy answer, seconds.
const RETRY_AFTER_S: u64 = 1;

/// At most `count` requests of a group of endpoints at work; the others wait a bounded time.
pub(crate) struct Slots {
    semaphore: Arc<Semaphore>,
    count: usize,
    /// The endpoints sharing the slots, for messages (`/api/detect, /api/photo and
    /// /api/propose`).
    endpoints: &'static str,
    wait: Duration,
}

impl Slots {
    pub(crate) fn new(endpoints: &'static str, count: usize, wait: Duration) -> Self {
        Self {
            semaphore: Arc::new(Semaphore::new(count)),
            count,
            endpoints,
            wait,
        }
    }

    /// A slot, held until the permit is dropped: move it into the blocking work, so that
    /// the slot stays taken while the work runs even if the client has gone.
    ///
    /// `endpoint` is the one asking, named in the busy answer.
    ///
    /// # Errors
    /// 503 with `Retry-After` when no slot frees within the wait, or when the server stops.
    pub(crate) async fn take(
        &self,
        endpoint: &'static str,
    ) -> Result<OwnedSemaphorePermit, ApiError> {
        let acquire = Arc::clone(&self.semaphore).acquire_owned();
        match tokio::time::timeout(self.wait, acquire).await {
            Ok(Ok(permit)) => Ok(permit),
            Ok(Err(_closed)) => Err(ApiError::new(
                StatusCode::SERVICE_UNAVAILABLE,
                "the server is shutting down",
            )),
            Err(_elapsed) => Err(ApiError::new(
                StatusCode::SERVICE_UNAVAILABLE,
                if self.endpoints == endpoint {
                    format!(
                        "the server is busy: {} {endpoint} requests are being worked on (the most it takes at once) and none finished within {} s; try again in a moment",
                        self.count,
                        self.wait.as_secs_f64()
                    )
                } else {
                    format!(
                        "the server is busy with {endpoint}: {} requests of {} (which share their slots) are being worked on (the most it takes at once) and none finished within {} s; try again in a moment",
                        self.count,
                        self.endpoints,
                        self.wait.as_secs_f64()
                    )
                },
            )
            .retry_after(RETRY_AFTER_S)),
        }
    }
}
