//! `vpmap serve`: the local web page (annotate a photo, see its map, 3D model and path).

use std::net::SocketAddr;
use std::sync::Arc;

use anyhow::Result;
use vpmap_web::{ServeOptions, is_loopback, serve_until_ctrl_c};

/// Arguments of `vpmap serve`.
#[derive(clap::Args)]
pub struct ServeArgs {
    /// Address to listen on. Keep the default (this machine only) unless you mean to let
    /// other machines use the page: it has no passwords.
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    /// Port to listen on (0 picks a free one, printed at start).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
}

fn announce(addr: SocketAddr) {
    if !is_loopback(addr.ip()) {
        eprintln!(
            "warning: listening on {addr}, which is NOT a loopback address: anyone who can reach this machine on port {} can use the page and make it compute, without a password. Use the default --host 127.0.0.1 unless you mean that.",
            addr.port()
        );
    }
    let url_host = match addr {
        SocketAddr::V4(v4) => v4.ip().to_string(),
        SocketAddr::V6(v6) => format!("[{}]", v6.ip()),
    };
    println!(
        "vpmap: serving http://{url_host}:{}/ (Ctrl-C to stop)",
        addr.port()
    );
}

/// `vpmap serve`.
pub fn run(args: &ServeArgs) -> Result<()> {
    let options = ServeOptions {
        log: Some(Arc::new(|line: &str| eprintln!("error: {line}"))),
    };
    serve_until_ctrl_c(&args.host, args.port, options, announce)?;
    println!("vpmap: stopped");
    Ok(())
}
