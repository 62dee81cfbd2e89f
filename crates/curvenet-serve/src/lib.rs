//! `curvenet serve`: a network's stability over a local JSON API, following a designer's
//! edits.
//!
//! A [`Design`] holds the network's [`curvenet::stability::Analyzer`] and the current
//! structure behind one lock, each edit warm-started from a nearby equilibrium and every
//! structure analysed kept in a [`cache::Cache`] (with its physical analysis in the physical
//! mode); a [`Runner`] runs the greedy on it, one run at a time on a thread of its own
//! ([`greedy`]), a [`LocalRunner`] the local search from the current structure ([`local`]);
//! [`constraints`] holds the session's design constraints, which both searches honour;
//! [`words`] spells the library's messages in the API's words (its JSON fields);
//! a [`Workspace`] ties them to one network, and [`workspace::open_run`] makes one of a run
//! folder; [`export`] writes the current structure as a file; [`api::router`] answers HTTP
//! requests about the current workspace (docs/serve.md; loading a run folder replaces it) and
//! serves the page of [`app`] at `/` (the viewer grown into a design tool), running every
//! analysis off the async runtime; [`Server`] binds a socket and serves the router on a tokio
//! runtime of its own; [`start`] is how a front end starts one (the socket, then what is
//! served, read by the application layer); [`bench`] measures edit latencies against cold
//! analyses, [`bench_draw`] the time of adding a curve. The core
//! library stays free of tokio: only this crate (and the command line's `serve` feature)
//! depends on it.

pub mod api;
pub mod app;
pub mod bench;
pub mod bench_draw;
pub mod cache;
pub mod constraints;
pub mod design;
pub mod export;
pub mod greedy;
mod job;
pub mod local;
pub mod slide;
pub mod start;
pub mod words;
pub mod workspace;

pub use api::{AppState, ServeConfig, router};
pub use design::{Design, DesignError, Edited, Evaluated, Source, Status, Summary};
pub use greedy::{Progress, RunStatus, Runner, Step};
pub use local::{LocalProgress, LocalRunner};
pub use workspace::Workspace;

use std::net::SocketAddr;

/// A bound server: the socket is listening once [`Server::bind`] returns (a busy port fails
/// before any analysis), and [`Server::run`] serves a design on it.
#[derive(Debug)]
pub struct Server {
    runtime: tokio::runtime::Runtime,
    listener: tokio::net::TcpListener,
}

impl Server {
    /// Binds `addr` (port 0: any free port).
    ///
    /// # Errors
    ///
    /// The runtime cannot start or the address cannot be bound.
    pub fn bind(addr: SocketAddr) -> std::io::Result<Self> {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()?;
        let listener = runtime.block_on(tokio::net::TcpListener::bind(addr))?;
        Ok(Server { runtime, listener })
    }

    /// The address the server listens on.
    ///
    /// # Errors
    ///
    /// The socket's address cannot be read.
    pub fn local_addr(&self) -> std::io::Result<SocketAddr> {
        self.listener.local_addr()
    }

    /// Serves requests about `design` until the process ends (or the listener fails).
    ///
    /// # Errors
    ///
    /// The listener failed.
    pub fn run(self, design: Design) -> std::io::Result<()> {
        let ws = Workspace::new(design, "network");
        self.serve(AppState::new(ws, ServeConfig::default()))
    }

    /// Serves requests about `app` (a workspace and the configuration) until the process ends
    /// (or the listener fails).
    ///
    /// # Errors
    ///
    /// The listener failed.
    pub fn serve(self, app: AppState) -> std::io::Result<()> {
        let Server { runtime, listener } = self;
        let app = router(app);
        runtime.block_on(async move { axum::serve(listener, app).await })
    }
}

/// The URL to announce for a server listening on `addr`: a loopback address in place of an
/// unspecified one (`0.0.0.0` listens on loopback too).
pub fn url(addr: SocketAddr) -> String {
    let ip = match addr.ip() {
        std::net::IpAddr::V4(ip) if ip.is_unspecified() => std::net::Ipv4Addr::LOCALHOST.into(),
        std::net::IpAddr::V6(ip) if ip.is_unspecified() => std::net::Ipv6Addr::LOCALHOST.into(),
        ip => ip,
    };
    format!("http://{}", SocketAddr::new(ip, addr.port()))
}
