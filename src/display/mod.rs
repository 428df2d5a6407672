//! Showing a render while it is made, in the tev image viewer over TCP ([`tev`]'s packets), as
//! pbrt-v4 does: the image is created at its full size, then each band of rows is sent as it
//! is finished, in tiles. The connection never fails a render and holds it up only so long:
//! connecting happens on a thread of its own; each packet has 3 s in all to be taken, or tev is
//! taken to have stopped reading and the connection is dropped; a lost or dropped connection is
//! made again after a wait (1 s, doubling with each failure up to 30 s), and then everything
//! shown so far is sent again. At the end the connection is closed without waiting for tev:
//! the system delivers what is still on its way. Each kind of failure is one warning.

pub mod tev;

use std::io::{self, Write};
use std::net::{Shutdown, TcpStream, ToSocketAddrs};
use std::str::FromStr;
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::{Duration, Instant};

use crate::math::Colour;
use crate::render::PixelBounds;

/// Longest wait for a connection to one address.
const CONNECT_TIMEOUT: Duration = Duration::from_millis(500);
/// The time a packet has, all told, to be taken by tev; past it tev is taken to have stopped
/// reading. A packet is a tile of at most [`TILE`] × [`TILE`] pixels: 192 KiB and a header.
const WRITE_TIMEOUT: Duration = Duration::from_secs(3);
/// The wait after a first failure to connect (or a connection lost or dropped) before the next
/// attempt; it doubles with each failure after it.
const RETRY: Duration = Duration::from_secs(1);
/// The longest wait between attempts; also how long a connection takes bands before the wait
/// goes back to [`RETRY`].
const RETRY_MAX: Duration = Duration::from_secs(30);
/// Longest wait at the end of a render for a connection under way.
const FINISH_WAIT: Duration = Duration::from_secs(3);
/// Tiles are at most this many pixels on a side (as pbrt-v4 sends them).
const TILE: u32 = 128;
/// Bytes a pixel takes in the copy kept for sending again: R, G, B as f32.
const KEPT_PER_PIXEL: u64 = size_of::<[f32; 3]>() as u64;
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

/// Bytes a [`Viewer`] of a render of `pixels` pixels holds: the copy it keeps for sending
/// again (none above 1 GiB), 12 bytes a pixel.
pub fn memory_needed(pixels: u64) -> u64 {
    let bytes = pixels.saturating_mul(KEPT_PER_PIXEL);
    if bytes <= MAX_KEPT { bytes } else { 0 }
}

/// A pixel as tev is sent it: linear R, G, B as f32 (as the EXR holds them).
trait Rgb {
    fn rgb(&self) -> [f32; 3];
}

impl Rgb for [f32; 3] {
    fn rgb(&self) -> [f32; 3] {
        *self
    }
}

impl Rgb for Colour {
    fn rgb(&self) -> [f32; 3] {
        [self.x as f32, self.y as f32, self.z as f32]
    }
}

/// The connection to tev.
enum Link {
    /// A connection being made on its own thread.
    Connecting(Receiver<io::Result<TcpStream>>),
    /// Connected; since when the image has been shown on it (`None`: not created yet).
    Up(TcpStream, Option<Instant>),
    /// Lost, or not made, at that time; tried again [`Viewer::wait`] after it.
    Down(Instant),
}

/// What went wrong with tev: each kind is reported once.
#[derive(Clone, Copy, PartialEq)]
enum Failure {
    Connect,
    Lost,
    /// tev took no packet in time.
    Stalled,
}

impl Failure {
    /// The failure of a connection that could not send or close with `e`.
    fn of(e: &io::Error) -> Failure {
        match e.kind() {
            io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut => Failure::Stalled,
            _ => Failure::Lost,
        }
    }
}

/// The image in tev: its name, its CreateImage packet and the pixels rendered.
struct Image {
    name: String,
    create: Vec<u8>,
    bounds: PixelBounds,
}

impl Image {
    /// Sends the rows from `y0` whose pixels (row by row across the bounds) are `pixels`, as
    /// UpdateImage packets of tiles of at most [`TILE`] × [`TILE`] pixels, converted tile by
    /// tile.
    fn update<P: Rgb>(&self, stream: &mut TcpStream, y0: u32, pixels: &[P]) -> io::Result<()> {
        let (x0, width) = (self.bounds.x0, self.bounds.width());
        let rows = pixels.len().checked_div(width as usize).unwrap_or(0) as u32;
        let mut tile = Vec::new();
        for ty in (0..rows).step_by(TILE as usize) {
            let th = TILE.min(rows - ty);
            for tx in (0..width).step_by(TILE as usize) {
                let tw = TILE.min(width - tx);
                tile.clear();
                for y in ty..ty + th {
                    let at = y as usize * width as usize + tx as usize;
                    tile.extend(pixels[at..at + tw as usize].iter().flat_map(Rgb::rgb));
                }
                let packet = tev::update_image(&self.name, x0 + tx, y0 + ty, tw, th, &tile)
                    .ok_or_else(|| io::Error::other("a tile beyond the sizes tev takes"))?;
                send(stream, &packet)?;
            }
        }
        Ok(())
    }

    /// Creates the image, then sends the rows from `y0` as [`Image::update`] does.
    fn create<P: Rgb>(&self, stream: &mut TcpStream, y0: u32, pixels: &[P]) -> io::Result<()> {
        send(stream, &self.create)?;
        self.update(stream, y0, pixels)
    }
}

/// A render shown in tev as it is made, to be told each finished band of rows, in order, top
/// to bottom ([`Viewer::show`]), and [`Viewer::finish`]ed.
pub struct Viewer {
    server: Server,
    image: Image,
    /// The pixels shown so far, from `bounds.y0`; `None` if too large to keep.
    kept: Option<Vec<[f32; 3]>>,
    link: Link,
    /// How long after a failure the next attempt waits (zero before any failure).
    wait: Duration,
    /// The kinds of failure reported.
    warned: Vec<Failure>,
    warn: Box<dyn FnMut(&str)>,
}

impl Viewer {
    /// Starts showing an image `name` of `width` × `height` pixels, of which `bounds` are
    /// rendered, in tev at `server`, keeping a copy of what is shown to send again after a
    /// reconnect; `warn` is told what goes wrong (one line, without a prefix). `None` (and a
    /// warning) if the image is too large for tev.
    pub fn new(
        server: Server,
        name: &str,
        width: u32,
        height: u32,
        bounds: PixelBounds,
        warn: Box<dyn FnMut(&str)>,
    ) -> Option<Viewer> {
        let mut viewer = Viewer::open(server, name, width, height, bounds, warn)?;
        let pixels = bounds.pixels();
        let mut kept = Vec::new();
        let bytes = memory_needed(pixels);
        if bytes > 0 && kept.try_reserve_exact(pixels as usize).is_ok() {
            viewer.kept = Some(kept);
        } else {
            let message = format!(
                "tev at {}: the image is too large to keep a copy of ({:.1} GiB), so after a \
                 reconnect tev shows only the rows rendered since",
                viewer.server,
                (pixels * KEPT_PER_PIXEL) as f64 / f64::from(1 << 30)
            );
            (viewer.warn)(&message);
        }
        Some(viewer)
    }

    /// Shows a finished image `name` of `width` × `height` pixels, `colours` (row by row), in
    /// tev at `server`, as [`Viewer::finish`] ends a render: waits (a little) for the
    /// connection, sends the image and closes the connection; `warn` is told what goes wrong.
    pub fn show_image(
        server: Server,
        name: &str,
        width: u32,
        height: u32,
        colours: &[Colour],
        warn: Box<dyn FnMut(&str)>,
    ) {
        let bounds = PixelBounds::full(width, height);
        if let Some(viewer) = Viewer::open(server, name, width, height, bounds, warn) {
            viewer.end(Some(colours));
        }
    }

    /// Starts connecting to show the image, keeping nothing; `None` (and a warning) if the
    /// image is too large for tev.
    fn open(
        server: Server,
        name: &str,
        width: u32,
        height: u32,
        bounds: PixelBounds,
        mut warn: Box<dyn FnMut(&str)>,
    ) -> Option<Viewer> {
        let Some(create) = tev::create_image(name, width, height) else {
            warn(&format!(
                "tev at {server}: an image of {width}x{height} pixels is too large for tev"
            ));
            return None;
        };
        Some(Viewer {
            link: Link::Connecting(connect(&server)),
            server,
            image: Image {
                name: name.to_string(),
                create,
                bounds,
            },
            kept: None,
            wait: Duration::ZERO,
            warned: Vec::new(),
            warn,
        })
    }

    /// Shows the band of rows from `y0` whose pixels (row by row across the bounds) are
    /// `colours`.
    pub fn show(&mut self, y0: u32, colours: &[Colour]) {
        if let Some(kept) = &mut self.kept {
            kept.extend(colours.iter().map(Rgb::rgb));
        }
        self.poll();
        let image = &self.image;
        let sent = match &mut self.link {
            Link::Up(stream, shown @ None) => {
                *shown = Some(Instant::now());
                match &self.kept {
                    Some(kept) => image.create(stream, image.bounds.y0, kept),
                    None => image.create(stream, y0, colours),
                }
            }
            Link::Up(stream, Some(since)) => {
                let sent = image.update(stream, y0, colours);
                // A connection that has lived and taken bands: the waits start again.
                if sent.is_ok() && since.elapsed() >= RETRY_MAX {
                    self.wait = Duration::ZERO;
                }
                sent
            }
            Link::Connecting(_) | Link::Down(_) => return,
        };
        if let Err(e) = sent {
            self.failed(Failure::of(&e), e);
        }
    }

    /// Ends the showing once the render is done: waits (a little) for a connection under
    /// way, and closes it (`close`); if the connection was down or turns out lost, tries
    /// once more to connect and send the whole image (unless the wait after the last failure
    /// is not over, or no copy was kept).
    pub fn finish(mut self) {
        let kept = self.kept.take();
        self.end(kept.as_deref());
    }

    /// [`Viewer::finish`], with `whole` the pixels of the bounds to send on a connection made
    /// now (`None`: nothing is sent on one).
    fn end<P: Rgb>(mut self, whole: Option<&[P]>) {
        loop {
            let image = &self.image;
            let outcome = match (&mut self.link, whole) {
                (Link::Up(stream, Some(_)), _) => match close(stream) {
                    Ok(()) => return,
                    closed => closed,
                },
                (Link::Connecting(pending), Some(_)) => {
                    let result = pending.recv_timeout(FINISH_WAIT);
                    self.connected(result.unwrap_or_else(|_| Err(stopped())));
                    Ok(())
                }
                (Link::Up(stream, shown @ None), Some(pixels)) => {
                    *shown = Some(Instant::now());
                    image.create(stream, image.bounds.y0, pixels)
                }
                (Link::Down(at), Some(_)) if at.elapsed() >= self.wait => {
                    self.link = Link::Connecting(connect(&self.server));
                    Ok(())
                }
                _ => return,
            };
            if let Err(e) = outcome {
                self.failed(Failure::of(&e), e);
            }
        }
    }

    /// Takes a connection made, or starts one once the wait after a failure is over.
    fn poll(&mut self) {
        match &self.link {
            Link::Connecting(pending) => match pending.try_recv() {
                Ok(result) => self.connected(result),
                Err(TryRecvError::Empty) => {}
                Err(TryRecvError::Disconnected) => self.connected(Err(stopped())),
            },
            Link::Down(at) if at.elapsed() >= self.wait => {
                self.link = Link::Connecting(connect(&self.server));
            }
            Link::Up(..) | Link::Down(_) => {}
        }
    }

    /// Takes the outcome of connecting.
    fn connected(&mut self, result: io::Result<TcpStream>) {
        match result {
            Ok(stream) => self.link = Link::Up(stream, None),
            Err(e) => self.failed(Failure::Connect, e),
        }
    }

    /// Drops the connection after `failure` (`e`), reporting it if it is the first of its
    /// kind; the next attempt waits twice as long as the last (from [`RETRY`] up to
    /// [`RETRY_MAX`]).
    fn failed(&mut self, failure: Failure, e: io::Error) {
        self.link = Link::Down(Instant::now());
        self.wait = (self.wait * 2).clamp(RETRY, RETRY_MAX);
        if self.warned.contains(&failure) {
            return;
        }
        self.warned.push(failure);
        let what = match failure {
            Failure::Connect => format!("cannot connect: {e}"),
            Failure::Lost => format!("the connection was lost: {e}"),
            Failure::Stalled => format!(
                "it took no data for {} s, so the connection was dropped",
                WRITE_TIMEOUT.as_secs()
            ),
        };
        let message = format!(
            "tev at {}: {what}; trying again while rendering, after {} s, then waiting twice as \
             long after each failure, up to {} s",
            self.server,
            RETRY.as_secs(),
            RETRY_MAX.as_secs()
        );
        (self.warn)(&message);
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

/// Fails if the connection is gone, without waiting: tev sends nothing, so the end of the
/// stream (tev closed its end, or quit) or an error is all there can be to read.
fn check_open(stream: &TcpStream) -> io::Result<()> {
    stream.set_nonblocking(true)?;
    let peeked = stream.peek(&mut [0]);
    stream.set_nonblocking(false)?;
    match peeked {
        Ok(0) => Err(io::Error::new(
            io::ErrorKind::UnexpectedEof,
            "tev closed it",
        )),
        Err(e) if e.kind() != io::ErrorKind::WouldBlock => Err(e),
        _ => Ok(()),
    }
}

/// Sends `packet` once [`check_open`] finds the connection there, within [`WRITE_TIMEOUT`] all
/// told (each write is given only the time left, so a tev that takes a little at a time
/// cannot stretch it); past it, an error of kind `TimedOut` or `WouldBlock`.
fn send(stream: &mut TcpStream, packet: &[u8]) -> io::Result<()> {
    check_open(stream)?;
    let deadline = Instant::now() + WRITE_TIMEOUT;
    let mut rest = packet;
    while !rest.is_empty() {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(io::ErrorKind::TimedOut.into());
        }
        stream.set_write_timeout(Some(left))?;
        match stream.write(rest) {
            Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
            Ok(n) => rest = &rest[n..],
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// Closes the connection once [`check_open`] finds it there (tev may have quit since the last
/// packet: then the connection was lost), without waiting for tev: the system delivers the
/// data still on its way and then the end of the stream, and a tev that reads everything but
/// never closes its end costs no wait. tev sends nothing, so nothing unread makes the close a
/// reset.
fn close(stream: &TcpStream) -> io::Result<()> {
    check_open(stream)?;
    stream.shutdown(Shutdown::Write)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;
    use std::io::Read;
    use std::net::TcpListener;
    use std::rc::Rc;

    /// A connected pair of loopback sockets: timbre's end and tev's.
    fn pair() -> (TcpStream, TcpStream) {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let ours = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        (ours, listener.accept().unwrap().0)
    }

    #[test]
    fn a_packet_has_one_deadline_however_the_reader_trickles() {
        let (mut ours, mut theirs) = pair();
        // tev takes 64 KiB every 20 ms (3 MiB/s), for at most 20 s: each write makes progress,
        // yet a packet of 64 MiB would take 20 s.
        let reader = std::thread::spawn(move || {
            let mut buffer = vec![0; 64 << 10];
            let until = Instant::now() + Duration::from_secs(20);
            theirs
                .set_read_timeout(Some(Duration::from_secs(1)))
                .unwrap();
            while Instant::now() < until && theirs.read(&mut buffer).is_ok_and(|n| n > 0) {
                std::thread::sleep(Duration::from_millis(20));
            }
        });
        let start = Instant::now();
        let e = send(&mut ours, &vec![0; 64 << 20]).unwrap_err();
        let took = start.elapsed();
        drop(ours);
        reader.join().unwrap();
        assert!(matches!(Failure::of(&e), Failure::Stalled), "{e}");
        // WRITE_TIMEOUT, not 20 s (a hang guard, not a measure of speed).
        assert!(took < Duration::from_secs(10), "{took:?}");
    }

    #[test]
    fn a_connection_closed_by_tev_is_found_without_waiting() {
        let (ours, theirs) = pair();
        check_open(&ours).unwrap();
        drop(theirs);
        let deadline = Instant::now() + Duration::from_secs(10);
        // The end of the stream arrives (on the loopback interface, at once).
        while check_open(&ours).is_ok() {
            assert!(Instant::now() < deadline, "the close never arrived");
            std::thread::sleep(Duration::from_millis(1));
        }
        let e = close(&ours).unwrap_err();
        assert!(matches!(Failure::of(&e), Failure::Lost), "{e}");
    }

    #[test]
    fn a_tev_that_reads_everything_but_never_closes_is_sent_the_image_without_a_warning() {
        let (ours, mut theirs) = pair();
        // tev reads to the end of the stream, then holds its end open until the test is done.
        let (done, held) = mpsc::channel::<()>();
        let reader = std::thread::spawn(move || {
            theirs
                .set_read_timeout(Some(Duration::from_secs(300)))
                .unwrap();
            let mut bytes = Vec::new();
            theirs.read_to_end(&mut bytes).unwrap();
            let _ = held.recv();
            bytes
        });
        let warnings = Rc::new(RefCell::new(Vec::new()));
        let told = warnings.clone();
        let colours = [Colour::new(0.25, 0.5, 1.0), Colour::new(3.0, 0.0, -1.0)];
        let viewer = Viewer {
            server: "127.0.0.1:1".parse().unwrap(),
            image: Image {
                name: "a".into(),
                create: tev::create_image("a", 2, 1).unwrap(),
                bounds: PixelBounds::full(2, 1),
            },
            kept: None,
            link: Link::Up(ours, None),
            wait: Duration::ZERO,
            warned: Vec::new(),
            warn: Box::new(move |m| told.borrow_mut().push(m.to_string())),
        };
        viewer.end(Some(&colours[..]));
        done.send(()).unwrap();
        let bytes = reader.join().unwrap();
        assert!(warnings.borrow().is_empty(), "{:?}", warnings.borrow());
        let rgb = [0.25, 0.5, 1.0, 3.0, 0.0, -1.0];
        let mut sent = tev::create_image("a", 2, 1).unwrap();
        sent.extend(tev::update_image("a", 0, 0, 2, 1, &rgb).unwrap());
        assert_eq!(bytes, sent);
    }

    #[test]
    fn failures_are_reported_once_a_kind_and_tried_again_ever_later() {
        let warnings = Rc::new(RefCell::new(Vec::new()));
        let told = warnings.clone();
        let mut viewer = Viewer {
            server: "127.0.0.1:1".parse().unwrap(),
            image: Image {
                name: "a".into(),
                create: Vec::new(),
                bounds: PixelBounds::full(1, 1),
            },
            kept: None,
            link: Link::Down(Instant::now()),
            wait: Duration::ZERO,
            warned: Vec::new(),
            warn: Box::new(move |m| told.borrow_mut().push(m.to_string())),
        };
        let kinds = [Failure::Connect, Failure::Lost, Failure::Stalled];
        let waits: Vec<u64> = (0..8)
            .map(|i| {
                viewer.failed(kinds[i % 3], io::Error::other("x"));
                viewer.wait.as_secs()
            })
            .collect();
        assert_eq!(waits, [1, 2, 4, 8, 16, 30, 30, 30]);
        let warnings = warnings.borrow();
        assert_eq!(warnings.len(), 3, "{warnings:?}");
        for (warning, what) in warnings
            .iter()
            .zip(["cannot connect", "lost", "took no data"])
        {
            assert!(warning.contains(what), "{warning}");
        }
    }

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
