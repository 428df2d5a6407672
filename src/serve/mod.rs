//! `timbre serve`: TIM, interactive again. A local web server (axum on tokio) with one page,
//! built into the binary, that shows a progressive render of a scene file and changes it:
//! navigation, every numeric value (with the semantics of `--set`), the scene text, a pixel's
//! contents, ray trajectories from a pixel, and a full-quality render to a file.
//!
//! One engine thread owns the [`Preview`]; the page's messages change its inputs and wake it,
//! and every connected page receives the same frames (binary WebSocket messages) and state
//! (JSON). See docs/PREVIEW.md for the protocol and the security rules.

mod engine;
mod messages;
mod page;
pub mod parameters;
pub mod preview;
mod protocol;

use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;

use thiserror::Error;

pub use preview::{Inspection, LoadError, Preview, PreviewOptions};

use crate::scene::file::Override;

/// Largest WebSocket message the server reads (a scene text edited in the page, with room for
/// the JSON around it), in bytes.
pub const MAX_MESSAGE_BYTES: usize = 4 << 20;

/// Most pages connected at once.
pub const MAX_CONNECTIONS: usize = 16;

/// Most visitors of a public server at once (`--visitors`).
pub const MAX_VISITORS: usize = 64;

/// A public server ([`ServeOptions::public`]): each visitor has an engine and a view of their
/// own, on the same scene, and no files are read or written for a page.
#[derive(Debug, Clone, Copy)]
pub struct Public {
    /// Most visitors at once; more are told the server is busy.
    pub visitors: usize,
}

/// What `timbre serve` was asked for.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    pub scene: PathBuf,
    pub bind: IpAddr,
    pub port: u16,
    /// `--set` overrides from the command line, under the page's own.
    pub overrides: Vec<Override>,
    pub preview: PreviewOptions,
    /// Serve anonymous visitors (`--public`), each with their own view and changes.
    pub public: Option<Public>,
}

/// Why the server could not start or stopped.
#[derive(Debug, Error)]
pub enum ServeError {
    /// The scene file cannot be read (the user's to fix: exit code 2).
    #[error("{0}")]
    Scene(String),
    /// The address cannot be listened on.
    #[error("cannot listen on {address}: {source}")]
    Listen {
        address: SocketAddr,
        source: std::io::Error,
    },
    #[error("{0}")]
    Internal(String),
}

/// Who may use the server: anyone on this machine when it listens on a loopback address,
/// otherwise those who know the token printed at start.
#[derive(Debug, Clone)]
pub struct Access {
    /// Required in every request (`?token=`), unless bound to loopback only.
    pub token: Option<String>,
    pub loopback: bool,
}

impl Access {
    /// The access rule of a public server: anyone, from anywhere, under any host name (it reads
    /// and writes no file for its pages).
    pub fn public() -> Access {
        Access {
            token: None,
            loopback: false,
        }
    }

    /// The access rule for listening on `bind`: a fresh random token unless it is a loopback
    /// address.
    pub fn for_address(bind: IpAddr) -> std::io::Result<Access> {
        let loopback = bind.is_loopback();
        let token = if loopback {
            None
        } else {
            Some(random_token()?)
        };
        Ok(Access { token, loopback })
    }
}

/// 128 random bits from the kernel, as 32 hexadecimal digits.
fn random_token() -> std::io::Result<String> {
    use std::io::Read;
    let mut bytes = [0u8; 16];
    std::fs::File::open("/dev/urandom")?.read_exact(&mut bytes)?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// Runs the server until the process is stopped: reads the scene, listens, prints the page's
/// address (with the token, if one is needed) on standard output and serves.
pub fn serve(mut options: ServeOptions) -> Result<(), ServeError> {
    // A public server's previews are each a visitor's: bounded, on one thread unless told.
    if options.public.is_some() {
        options.preview.public = true;
        options.preview.threads.get_or_insert(1);
    }
    let text = engine::read_scene(&options.scene).map_err(ServeError::Scene)?;
    let access = match options.public {
        Some(_) => Access::public(),
        None => Access::for_address(options.bind)
            .map_err(|e| ServeError::Internal(format!("cannot make an access token: {e}")))?,
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| ServeError::Internal(e.to_string()))?;
    runtime.block_on(async move {
        let address = SocketAddr::new(options.bind, options.port);
        let listener = tokio::net::TcpListener::bind(address)
            .await
            .map_err(|source| ServeError::Listen { address, source })?;
        let address = listener
            .local_addr()
            .map_err(|e| ServeError::Internal(e.to_string()))?;
        let engines = match options.public {
            // Each visitor's engine starts when they connect.
            Some(public) => protocol::Engines::PerVisitor {
                options: Box::new(options.clone()),
                text,
                most: public.visitors,
                visitors: Arc::new(std::sync::atomic::AtomicUsize::new(0)),
            },
            None => protocol::Engines::Shared(engine::Engine::start(&options, text, ())?),
        };
        let app = protocol::router(Arc::new(protocol::AppState::new(engines, access.clone())));
        {
            use std::io::Write as _;
            let host = match address {
                SocketAddr::V6(a) => format!("[{}]:{}", a.ip(), a.port()),
                a => a.to_string(),
            };
            let query = access
                .token
                .as_ref()
                .map_or(String::new(), |t| format!("?token={t}"));
            let mut out = std::io::stdout();
            let _ = writeln!(
                out,
                "timbre serve: {} on http://{host}/{query}",
                options.scene.display()
            );
            if let Some(public) = options.public {
                let _ = writeln!(
                    out,
                    "timbre serve: public: at most {} visitors at once, each on {} thread(s); no files read or written for a page",
                    public.visitors,
                    options.preview.threads.unwrap_or(1)
                );
            } else if access.token.is_some() {
                let _ = writeln!(
                    out,
                    "timbre serve: listening beyond this machine: the page needs the token above"
                );
            }
            let _ = out.flush();
        }
        axum::serve(listener, app)
            .await
            .map_err(|e| ServeError::Internal(e.to_string()))
    })
}
