//! Showing a render while it is made, in the tev image viewer over TCP ([`tev`]'s packets), as
//! pbrt-v4 does: the image is created at its full size, then each band of rows is sent as it
//! is finished, in tiles. The connection never holds up or fails a render: connecting happens
//! on a thread of its own, a lost connection is tried again at most once a second (and then
//! everything shown so far is sent again), and what goes wrong is one warning.

pub mod tev;

use std::io::{self, Read, Write};
use std::net::{Shutdown, TcpStream, ToSocketAddrs};
use std::str::FromStr;
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::{Duration, Instant};

use crate::math::Colour;
use crate::render::PixelBounds;

/// Longest wait for a connection to one address.
const CONNECT_TIMEOUT: Duration = Duration::from_millis(500);
/// A write that makes no progress for this long means tev stopped reading.
const WRITE_TIMEOUT: Duration = Duration::from_secs(3);
/// Least time between attempts to connect.
const RETRY: Duration = Duration::from_secs(1);
/// Longest wait at the end of a render: for a connection under way, and for tev to confirm it
/// has read everything.
const FINISH_WAIT: Duration = Duration::from_secs(3);
/// Tiles are at most this many pixels on a side (as pbrt-v4 sends them).
const TILE: u32 = 128;
/// The largest copy of the shown pixels kept for sending again after a reconnect.
const MAX_KEPT: u64 = 1 << 30;

/// Where tev listens: `HOST:PORT` (an IPv6 address in brackets: `[::1]:14158`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Server {
    host: String,
    port: u16,
}

impl FromStr for Server {
    type Err = String;

    fn from_str(s: &str) -> Result<Server, String> {
        let expected = || format!("expected HOST:PORT, e.g. 127.0.0.1:14158, got '{s}'");
        let (host, port) = s.rsplit_once(':').ok_or_else(expected)?;
        let port = match port.parse::<u16>() {
            Ok(p) if p > 0 && port.bytes().all(|b| b.is_ascii_digit()) => p,
            _ => return Err(format!("the port must be from 1 to 65535, got '{port}'")),
        };
        let bare = host
            .strip_prefix('[')
            .and_then(|h| h.strip_suffix(']'))
            .unwrap_or(host);
        if bare.is_empty() {
            return Err(expected());
        }
        if bare.contains(':') && bare.len() == host.len() {
            return Err(format!(
                "an IPv6 address goes in brackets, e.g. [::1]:14158, got '{s}'"
            ));
        }
        Ok(Server {
            host: bare.to_string(),
            port,
        })
    }
}

impl std::fmt::Display for Server {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.host.contains(':') {
            true => write!(f, "[{}]:{}", self.host, self.port),
            false => write!(f, "{}:{}", self.host, self.port),
        }
    }
}

/// The connection to tev.
enum Link {
    /// A connection being made on its own thread.
    Connecting(Receiver<io::Result<TcpStream>>),
    Up(TcpStream),
    /// Lost, or not made, at that time.
    Down(Instant),
    /// tev stopped reading: nothing more is sent.
    Off,
}

/// A render shown in tev as it is made, to be told each finished band of rows, in order, top
/// to bottom ([`Viewer::show`]), and [`Viewer::finish`]ed.
pub struct Viewer {
    server: Server,
    /// The image's name in tev.
    name: String,
    /// The whole image's size.
    width: u32,
    height: u32,
    /// The pixels rendered.
    bounds: PixelBounds,
    /// R, G, B of the rows shown so far, from `bounds.y0`; `None` if too large to keep.
    kept: Option<Vec<f32>>,
    /// R, G, B of the latest band, when nothing is kept.
    band: Vec<f32>,
    link: Link,
    /// Whether a failure to connect has been reported.
    warned: bool,
    warn: Box<dyn FnMut(&str)>,
}

impl Viewer {
    /// Starts showing an image `name` of `width` × `height` pixels, of which `bounds` are
    /// rendered, in tev at `server`; `warn` is told what goes wrong (one line, without a
    /// prefix).
    pub fn new(
        server: Server,
        name: &str,
        width: u32,
        height: u32,
        bounds: PixelBounds,
        mut warn: Box<dyn FnMut(&str)>,
    ) -> Viewer {
        let values = bounds.pixels() * 3;
        let bytes = values * size_of::<f32>() as u64;
        let mut kept = Vec::new();
        let fits = bytes <= MAX_KEPT && kept.try_reserve_exact(values as usize).is_ok();
        if !fits {
            warn(&format!(
                "tev at {server}: the image is too large to keep a copy of ({:.1} GiB), so after \
                 a reconnect tev shows only the rows rendered since",
                bytes as f64 / f64::from(1 << 30)
            ));
        }
        Viewer {
            link: Link::Connecting(connect(&server)),
            server,
            name: name.to_string(),
            width,
            height,
            bounds,
            kept: fits.then_some(kept),
            band: Vec::new(),
            warned: false,
            warn,
        }
    }

    /// Shows the band of rows from `y0` whose pixels (row by row across the bounds) are
    /// `colours`.
    pub fn show(&mut self, y0: u32, colours: &[Colour]) {
        let rgb = colours
            .iter()
            .flat_map(|c| [c.x as f32, c.y as f32, c.z as f32]);
        let start = match &mut self.kept {
            Some(kept) => {
                let start = kept.len();
                kept.extend(rgb);
                start
            }
            None => {
                self.band.clear();
                self.band.extend(rgb);
                0
            }
        };
        let sent = match &self.link {
            Link::Connecting(pending) => match pending.try_recv() {
                Ok(result) => self.connected(result),
                Err(TryRecvError::Empty) => false,
                Err(TryRecvError::Disconnected) => self.connected(Err(stopped())),
            },
            Link::Down(at) if at.elapsed() >= RETRY => {
                self.link = Link::Connecting(connect(&self.server));
                false
            }
            _ => false,
        };
        if let (false, Link::Up(stream)) = (sent, &mut self.link) {
            let band = self.kept.as_ref().map_or(&self.band[..], |k| &k[start..]);
            let (x0, width) = (self.bounds.x0, self.bounds.width());
            if let Err(e) = send_rows(stream, &self.name, x0, y0, width, band) {
                self.lost(e);
            }
        }
    }

    /// Ends the showing once the render is done: waits (a little) for a connection under
    /// way and for tev to read everything; if the connection was down or turns out lost, tries
    /// once more to connect and send the whole image (unless an attempt just failed).
    pub fn finish(mut self) {
        let mut tried = false;
        loop {
            match std::mem::replace(&mut self.link, Link::Off) {
                Link::Connecting(pending) => {
                    let result = pending.recv_timeout(FINISH_WAIT).map_err(|_| stopped());
                    let result = result.and_then(|r| r);
                    tried |= result.is_err();
                    self.connected(result);
                }
                Link::Up(stream) => match close(stream) {
                    Ok(()) => return,
                    Err(e) => self.lost(e),
                },
                Link::Down(_) if !tried && self.kept.is_some() => {
                    tried = true;
                    self.link = Link::Connecting(connect(&self.server));
                }
                Link::Down(_) | Link::Off => return,
            }
        }
    }

    /// Takes the outcome of connecting: once connected, the image is created and every kept
    /// row sent. Returns whether the rows were sent (so the latest band need not be).
    fn connected(&mut self, result: io::Result<TcpStream>) -> bool {
        let mut stream = match result {
            Ok(stream) => stream,
            Err(e) => {
                if !self.warned {
                    self.warned = true;
                    let message = format!(
                        "tev at {}: cannot connect: {e}; trying again every second while \
                         rendering",
                        self.server
                    );
                    (self.warn)(&message);
                }
                self.link = Link::Down(Instant::now());
                return false;
            }
        };
        let kept = self.kept.as_deref().unwrap_or_default();
        let (x0, y0, width) = (self.bounds.x0, self.bounds.y0, self.bounds.width());
        let sent = stream
            .write_all(&tev::create_image(&self.name, self.width, self.height))
            .and_then(|()| send_rows(&mut stream, &self.name, x0, y0, width, kept));
        match sent {
            Ok(()) => {
                self.link = Link::Up(stream);
                self.kept.is_some()
            }
            Err(e) => {
                self.lost(e);
                false
            }
        }
    }

    /// Drops a connection that failed with `e`: tev is tried again later, unless it stopped
    /// reading.
    fn lost(&mut self, e: io::Error) {
        let stalled = matches!(
            e.kind(),
            io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
        );
        let message = match stalled {
            true => format!(
                "tev at {}: it stopped reading; it is shown no more of this render",
                self.server
            ),
            false => format!(
                "tev at {}: the connection was lost: {e}; reconnecting",
                self.server
            ),
        };
        (self.warn)(&message);
        self.link = match stalled {
            true => Link::Off,
            false => Link::Down(Instant::now()),
        };
    }
}

/// The error of a connecting thread that gave no answer in time, or could not be started.
fn stopped() -> io::Error {
    io::Error::new(io::ErrorKind::TimedOut, "no connection was made in time")
}

/// Connects to `server` on a thread of its own (resolving the host there too, since that can
/// take long); the result comes through the receiver.
fn connect(server: &Server) -> Receiver<io::Result<TcpStream>> {
    let (sender, receiver) = mpsc::channel();
    let server = server.clone();
    let open = move || {
        let mut error = io::Error::new(io::ErrorKind::NotFound, "the host has no address");
        for address in (server.host.as_str(), server.port).to_socket_addrs()? {
            match TcpStream::connect_timeout(&address, CONNECT_TIMEOUT) {
                Ok(stream) => {
                    stream.set_nodelay(true)?;
                    stream.set_write_timeout(Some(WRITE_TIMEOUT))?;
                    return Ok(stream);
                }
                Err(e) => error = e,
            }
        }
        Err(error)
    };
    // A thread that cannot be started drops the sender: the receiver then reports that.
    let _ = std::thread::Builder::new()
        .name("tev".into())
        .spawn(move || sender.send(open()));
    receiver
}

/// Sends the rows from `y0` whose R, G, B are `rgb` (row by row, `width` pixels from `x0`) as
/// UpdateImage packets of tiles of at most [`TILE`] × [`TILE`] pixels.
fn send_rows(
    stream: &mut TcpStream,
    name: &str,
    x0: u32,
    y0: u32,
    width: u32,
    rgb: &[f32],
) -> io::Result<()> {
    let row = 3 * width as usize;
    let rows = rgb.len().checked_div(row).unwrap_or(0) as u32;
    let mut tile = Vec::new();
    for ty in (0..rows).step_by(TILE as usize) {
        let th = TILE.min(rows - ty);
        for tx in (0..width).step_by(TILE as usize) {
            let tw = TILE.min(width - tx);
            tile.clear();
            for y in ty..ty + th {
                let at = y as usize * row + 3 * tx as usize;
                tile.extend_from_slice(&rgb[at..at + 3 * tw as usize]);
            }
            stream.write_all(&tev::update_image(name, x0 + tx, y0 + ty, tw, th, &tile))?;
        }
    }
    Ok(())
}

/// Closes the connection once tev has read everything: tev closes its end when it reads the
/// end of the stream, which is all that tells a sender that the data arrived. An error means
/// the connection was lost (a reset: tev did not read it all).
fn close(stream: TcpStream) -> io::Result<()> {
    stream.shutdown(Shutdown::Write)?;
    let deadline = Instant::now() + FINISH_WAIT;
    let mut buffer = [0; 256];
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(io::ErrorKind::TimedOut.into());
        }
        stream.set_read_timeout(Some(left))?;
        if (&stream).read(&mut buffer)? == 0 {
            return Ok(());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn servers_are_host_and_port() {
        let s: Server = "127.0.0.1:14158".parse().unwrap();
        assert_eq!((s.host.as_str(), s.port), ("127.0.0.1", 14158));
        assert_eq!(s.to_string(), "127.0.0.1:14158");
        let s: Server = "[::1]:1".parse().unwrap();
        assert_eq!((s.host.as_str(), s.port), ("::1", 1));
        assert_eq!(s.to_string(), "[::1]:1");
        assert_eq!("tev.example:65535".parse::<Server>().unwrap().port, 65535);
        for bad in [
            "nohost",
            ":14158",
            "[]:14158",
            "host:",
            "host:0",
            "host:65536",
            "host:-1",
            "host:+5",
            "host:1x",
            "::1:14158",
        ] {
            assert!(bad.parse::<Server>().is_err(), "{bad} was accepted");
        }
    }
}
