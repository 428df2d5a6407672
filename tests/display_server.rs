//! `timbre render --display-server HOST:PORT`: a fake tev server on the loopback interface
//! reads every packet strictly as tev's IPC protocol lays it out (a u32 length counting
//! itself, a u8 type, then the fields, little-endian; CreateImage = 4, UpdateImage V3 = 6),
//! assembles the image from the updates and checks it against the EXR the render wrote, bit
//! for bit; also after the connection is dropped mid-render, for a part of the image, with no
//! tev at all, with one that never reads, one that reads everything but never closes, one that
//! closes at once or before the last band, and for bad values of the flag. Every wait is
//! bounded.

mod common;

use std::fs::File;
use std::io::{ErrorKind, Read};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread;
use std::time::{Duration, Instant};

use exr::prelude::FlatSamples;
use tempfile::TempDir;

use common::cli::{HANG, Run, TIMBRE};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/studio.toml");
/// tev reads packets into a buffer of 1 MiB (it grows it for larger ones); tiles stay below.
const LARGEST_PACKET: usize = 1 << 20;

/// Runs `timbre` with `args` in `dir`, as [`bounded`].
fn timbre(dir: &Path, args: &[&str]) -> Run {
    let mut command = Command::new(TIMBRE);
    command.args(args);
    bounded(dir, command)
}

/// Runs `command` (which runs `timbre`) in `dir`, killing it if it runs longer than [`HANG`].
fn bounded(dir: &Path, mut command: Command) -> Run {
    let out = |name: &str| File::create(dir.join(name)).unwrap();
    let mut child = command
        .current_dir(dir)
        .stdout(out("timbre.stdout"))
        .stderr(out("timbre.stderr"))
        .spawn()
        .expect("run timbre");
    let deadline = Instant::now() + HANG;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("{command:?} ran longer than {HANG:?}");
        }
        thread::sleep(Duration::from_millis(10));
    };
    let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
    Run {
        code: status.code(),
        stdout: read("timbre.stdout"),
        stderr: read("timbre.stderr"),
    }
}

/// `timbre render` of the studio, `width` × 64 pixels with 2 samples per pixel, into
/// `dir/out.exr`, with `more` arguments.
fn render(dir: &Path, width: &str, more: &[&str]) -> Run {
    let mut args = vec![
        "render", SCENE, "--width", width, "--height", "64", "--spp", "2", "-o", "out.exr",
    ];
    args.extend_from_slice(more);
    timbre(dir, &args)
}

/// A tev packet, as read.
#[derive(Debug)]
enum Packet {
    Create {
        name: String,
        width: u32,
        height: u32,
    },
    Update {
        name: String,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        /// R, G, B of each pixel, row by row.
        rgb: Vec<[f32; 3]>,
    },
}

/// Reads the fields of one packet, refusing anything out of place.
struct Fields<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Fields<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        assert!(
            self.at + n <= self.bytes.len(),
            "a field runs past the end of the packet"
        );
        self.at += n;
        &self.bytes[self.at - n..self.at]
    }

    fn bool(&mut self) -> bool {
        match self.take(1)[0] {
            0 => false,
            1 => true,
            b => panic!("a bool of {b}"),
        }
    }

    fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.take(4).try_into().unwrap())
    }

    /// A count or a size: an int32 that must not be negative.
    fn size(&mut self) -> u32 {
        u32::try_from(self.i32()).expect("a size of at least 0")
    }

    fn i64(&mut self) -> i64 {
        i64::from_le_bytes(self.take(8).try_into().unwrap())
    }

    fn string(&mut self) -> String {
        let rest = &self.bytes[self.at..];
        let end = rest
            .iter()
            .position(|&b| b == 0)
            .expect("a string ends with NUL");
        let text = String::from_utf8(rest[..end].to_vec()).expect("UTF-8");
        self.at += end + 1;
        text
    }

    /// The channel count and names: R, G, B.
    fn channels(&mut self) {
        let n = self.size();
        let names: Vec<String> = (0..n).map(|_| self.string()).collect();
        assert_eq!(names, ["R", "G", "B"]);
    }
}

/// Parses one whole packet (its length included).
fn parse(bytes: &[u8]) -> Packet {
    let mut f = Fields { bytes, at: 0 };
    assert_eq!(f.size() as usize, bytes.len());
    assert!(
        bytes.len() <= LARGEST_PACKET,
        "a packet of {} bytes",
        bytes.len()
    );
    let packet = match f.take(1)[0] {
        4 => {
            assert!(f.bool(), "a new image takes the focus");
            let name = f.string();
            let (width, height) = (f.size(), f.size());
            f.channels();
            Packet::Create {
                name,
                width,
                height,
            }
        }
        6 => {
            f.bool();
            let name = f.string();
            f.channels();
            let (x, y, width, height) = (f.size(), f.size(), f.size(), f.size());
            let offsets: Vec<i64> = (0..3).map(|_| f.i64()).collect();
            let strides: Vec<i64> = (0..3).map(|_| f.i64()).collect();
            let pixels = width as usize * height as usize;
            assert!(pixels > 0, "an empty update");
            // As tev reads it: value c of pixel p at offset[c] + p * stride[c].
            let at = |c: usize, p: usize| {
                let (offset, stride) = (offsets[c], strides[c]);
                assert!(
                    offset >= 0 && stride >= 0,
                    "offset {offset}, stride {stride}"
                );
                offset as usize + p * stride as usize
            };
            let floats = (0..3).map(|c| at(c, pixels - 1) + 1).max().unwrap();
            let data = f.take(4 * floats);
            let value = |i: usize| f32::from_le_bytes(data[4 * i..4 * i + 4].try_into().unwrap());
            let rgb = (0..pixels)
                .map(|p| [0, 1, 2].map(|c| value(at(c, p))))
                .collect();
            Packet::Update {
                name,
                x,
                y,
                width,
                height,
                rgb,
            }
        }
        t => panic!("a packet of unknown type {t}"),
    };
    assert_eq!(f.at, bytes.len(), "bytes left over in a packet");
    packet
}

/// Waits for the next connection to `listener` (non-blocking); `None` once `done` is set and
/// none is waiting.
fn accept(listener: &TcpListener, done: &AtomicBool) -> Option<TcpStream> {
    let deadline = Instant::now() + HANG;
    loop {
        match listener.accept() {
            Ok((stream, _)) => {
                stream.set_nonblocking(false).unwrap();
                stream.set_read_timeout(Some(HANG)).unwrap();
                return Some(stream);
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock && done.load(Ordering::SeqCst) => {
                return None;
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock && Instant::now() < deadline => {
                thread::sleep(Duration::from_millis(1));
            }
            Err(e) => panic!("no connection: {e}"),
        }
    }
}

/// Reads packets until the end of the stream, or `limit` packets; an incomplete packet fails.
fn read_packets(stream: &mut TcpStream, limit: usize) -> Vec<Packet> {
    let mut packets = Vec::new();
    while packets.len() < limit {
        let mut length = [0; 4];
        match stream.read(&mut length[..1]) {
            Ok(0) => break,
            Ok(_) => stream.read_exact(&mut length[1..]).expect("a whole length"),
            Err(e) => panic!("reading: {e}"),
        }
        let n = u32::from_le_bytes(length) as usize;
        assert!((5..=LARGEST_PACKET).contains(&n), "a packet of {n} bytes");
        let mut bytes = length.to_vec();
        bytes.resize(n, 0);
        stream.read_exact(&mut bytes[4..]).expect("a whole packet");
        packets.push(parse(&bytes));
    }
    packets
}

/// A fake tev on a free loopback port, serving connection after connection on a thread until
/// timbre is done.
struct FakeTev {
    address: String,
    done: Arc<AtomicBool>,
    server: thread::JoinHandle<Vec<Vec<Packet>>>,
}

impl FakeTev {
    /// Serves each connection as `serve` does, told its index; `serve` returns the packets
    /// read.
    fn new(mut serve: impl FnMut(usize, TcpStream) -> Vec<Packet> + Send + 'static) -> FakeTev {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        listener.set_nonblocking(true).unwrap();
        let address = listener.local_addr().unwrap().to_string();
        let done = Arc::new(AtomicBool::new(false));
        let stop = done.clone();
        let server = thread::spawn(move || {
            let mut connections = Vec::new();
            while let Some(stream) = accept(&listener, &stop) {
                connections.push(serve(connections.len(), stream));
            }
            connections
        });
        FakeTev {
            address,
            done,
            server,
        }
    }

    /// Reads connection `i` to `limits[i]` packets (`usize::MAX`, and connections past the
    /// list: to the end), then closes it.
    fn reading(limits: Vec<usize>) -> FakeTev {
        FakeTev::new(move |i, mut stream| {
            read_packets(&mut stream, limits.get(i).copied().unwrap_or(usize::MAX))
        })
    }

    /// The packets of each connection served, once timbre has exited (connections not made
    /// by then are not waited for).
    fn connections(self) -> Vec<Vec<Packet>> {
        self.done.store(true, Ordering::SeqCst);
        self.server.join().unwrap()
    }
}

/// A loopback port that nothing listens on, nor can while the returned sockets live: it is
/// the local port of a connected socket (bound without SO_REUSEADDR, so no listener can bind
/// it, and the system hands it to no socket bound to port 0), so tests running beside this one
/// cannot take it. The listener keeps the connection (and so the port) alive.
fn refusing_port() -> ((TcpListener, TcpStream), u16) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
    let port = client.local_addr().unwrap().port();
    ((listener, client), port)
}

/// A rectangle of pixels: x, y, width, height.
type Rect = (u32, u32, u32, u32);

/// The image tev would show after `packets`: its name and size, and each pixel's R, G, B where
/// an update set it and how many updates did; also the rectangles updated.
struct Shown {
    name: String,
    width: u32,
    height: u32,
    pixels: Vec<Option<[f32; 3]>>,
    writes: Vec<u32>,
    updates: Vec<Rect>,
}

fn assemble(packets: &[Packet]) -> Shown {
    let Some(Packet::Create {
        name,
        width,
        height,
    }) = packets.first()
    else {
        panic!("the first packet creates the image: {:?}", packets.first());
    };
    let mut shown = Shown {
        name: name.clone(),
        width: *width,
        height: *height,
        pixels: vec![None; *width as usize * *height as usize],
        writes: vec![0; *width as usize * *height as usize],
        updates: Vec::new(),
    };
    for packet in &packets[1..] {
        let Packet::Update {
            name,
            x,
            y,
            width,
            height,
            rgb,
        } = packet
        else {
            panic!("the image is created again: {packet:?}");
        };
        assert_eq!(name, &shown.name);
        assert!(x + width <= shown.width && y + height <= shown.height);
        for (i, value) in rgb.iter().enumerate() {
            let (px, py) = (x + i as u32 % width, y + i as u32 / width);
            let at = (py * shown.width + px) as usize;
            shown.pixels[at] = Some(*value);
            shown.writes[at] += 1;
        }
        shown.updates.push((*x, *y, *width, *height));
    }
    shown
}

/// The R, G, B of an EXR file's pixels, its data window and the size of
/// its display window.
fn read_exr(path: &Path) -> (Vec<[f32; 3]>, Rect, (u32, u32)) {
    let image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    let layer = &image.layer_data[0];
    let channel = |name: &str| {
        let channel = layer.channel_data.list.iter();
        match channel
            .map(|c| (c.name.to_string(), &c.sample_data))
            .find(|c| c.0 == name)
        {
            Some((_, FlatSamples::F32(values))) => values.clone(),
            _ => panic!("no f32 channel {name}"),
        }
    };
    let (r, g, b) = (channel("R"), channel("G"), channel("B"));
    let rgb = (0..r.len()).map(|i| [r[i], g[i], b[i]]).collect();
    let p = layer.attributes.layer_position;
    let window = (
        p.0 as u32,
        p.1 as u32,
        layer.size.0 as u32,
        layer.size.1 as u32,
    );
    let full = image.attributes.display_window.size;
    (rgb, window, (full.0 as u32, full.1 as u32))
}

/// Asserts that `shown` is the EXR at `path`: its size, and within the EXR's data window its
/// pixels bit for bit, each updated exactly once; nothing outside is updated.
#[track_caller]
fn assert_shows(shown: &Shown, path: &Path) {
    let (rgb, (x0, y0, w, h), full) = read_exr(path);
    assert_eq!((shown.width, shown.height), full);
    let bits = |c: [f32; 3]| c.map(f32::to_bits);
    for y in 0..shown.height {
        for x in 0..shown.width {
            let got = shown.pixels[(y * shown.width + x) as usize];
            let inside = (x0..x0 + w).contains(&x) && (y0..y0 + h).contains(&y);
            if inside {
                let want = rgb[((y - y0) * w + x - x0) as usize];
                assert_eq!(got.map(bits), Some(bits(want)), "pixel ({x}, {y})");
                let writes = shown.writes[(y * shown.width + x) as usize];
                assert_eq!(writes, 1, "pixel ({x}, {y}) was sent {writes} times");
            } else {
                assert_eq!(got, None, "pixel ({x}, {y}) is outside the part rendered");
            }
        }
    }
}

/// The render time `timbre render` reported ("… rays in SECONDS s …").
fn reported_seconds(run: &Run) -> f64 {
    let after = run.stdout.split(" rays in ").nth(1);
    let seconds = after.and_then(|s| s.split_whitespace().next());
    seconds
        .and_then(|s| s.parse().ok())
        .expect("the summary line")
}

/// A render slow enough for timbre to reconnect during it (one thread, 640 samples per pixel:
/// about 4 s where 1.1 s are needed), 200 × 256 pixels (two tiles across), shown in tev at
/// `address`, into `dir/out.exr`; how long it took.
fn slow_render(dir: &Path, address: &str) -> (Run, Duration) {
    let start = Instant::now();
    let run = timbre(
        dir,
        &[
            "render",
            SCENE,
            "--width",
            "200",
            "--height",
            "256",
            "--spp",
            "640",
            "--threads",
            "1",
            "-o",
            "out.exr",
            "--display-server",
            address,
        ],
    );
    (run, start.elapsed())
}

/// A fake tev that accepts connections and never reads them (holding them open until timbre
/// is done).
fn deaf_tev() -> FakeTev {
    let mut held = Vec::new();
    FakeTev::new(move |_, stream| {
        held.push(stream);
        Vec::new()
    })
}

/// Checks that `stderr` is one warning about the tev at `address`, starting with `what`.
#[track_caller]
fn one_warning(stderr: &str, address: &str, what: &str) {
    let warning = format!("timbre: warning: tev at {address}: {what}");
    assert!(stderr.starts_with(&warning), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
}

#[test]
fn tev_is_shown_the_image_the_exr_holds_bit_for_bit() {
    let dir = TempDir::new().unwrap();
    let tev = FakeTev::reading(vec![]);
    let run = render(dir.path(), "96", &["--display-server", &tev.address]);
    run.assert_success();
    assert!(!run.stderr.contains("warning"), "{}", run.stderr);
    let connections = tev.connections();
    assert_eq!(connections.len(), 1);
    let shown = assemble(&connections[0]);
    assert_eq!(shown.name, "out.exr");
    assert_shows(&shown, &dir.path().join("out.exr"));
    // In tiles of at most 128 × 128 pixels.
    assert!(shown.updates.iter().all(|u| u.2 <= 128 && u.3 <= 128));
}

#[test]
fn a_tev_that_restarts_mid_render_is_sent_each_pixel_once_on_the_new_connection() {
    let dir = TempDir::new().unwrap();
    // The first connection is dropped once the image is created and one tile updated, while
    // the render goes on for seconds; the next is read to the end.
    let tev = FakeTev::reading(vec![2]);
    let (run, took) = slow_render(dir.path(), &tev.address);
    run.assert_success();
    one_warning(&run.stderr, &tev.address, "the connection was lost");
    let connections = tev.connections();
    assert_eq!(connections.len(), 2, "in {took:?}");
    assert!(matches!(
        connections[0][..],
        [Packet::Create { .. }, Packet::Update { .. }]
    ));
    let shown = assemble(&connections[1]);
    // The rows rendered before the reconnect are sent again in tiles of up to 128 rows, the
    // rest band by band (8 rows) as they are rendered: the last rows came in a band, so the
    // reconnect was during the render.
    let heights: Vec<u32> = shown.updates.iter().map(|u| u.3).collect();
    assert!(
        heights[0] > 8 && heights.last() == Some(&8),
        "timbre reconnected only at the end of the render ({took:?}; make it slower): \
         {heights:?}"
    );
    // Every pixel exactly once on the new connection, bit for bit.
    assert_shows(&shown, &dir.path().join("out.exr"));
}

#[test]
fn a_part_render_is_named_after_its_part_and_updates_only_its_rectangle() {
    let dir = TempDir::new().unwrap();
    let tev = FakeTev::reading(vec![]);
    let part = ["--pixel-bounds", "13,90,9,50", "--samples", "0..1"];
    let run = render(
        dir.path(),
        "96",
        &[&part[..], &["--display-server", &tev.address]].concat(),
    );
    run.assert_success();
    let shown = assemble(&tev.connections()[0]);
    // Parts streamed under the same output name do not replace one another in tev.
    assert_eq!(shown.name, "out.exr (pixels 13,90,9,50) (samples 0..1)");
    assert_eq!((shown.width, shown.height), (96, 64));
    let within =
        |&(x, y, w, h): &(u32, u32, u32, u32)| x >= 13 && x + w <= 90 && y >= 9 && y + h <= 50;
    assert!(shown.updates.iter().all(within), "{:?}", shown.updates);
    let path = dir.path().join("out.exr");
    assert_eq!(read_exr(&path).1, (13, 9, 77, 41));
    assert_shows(&shown, &path);
}

#[test]
fn with_no_tev_listening_the_render_is_the_same_and_warns_once() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let (_held, port) = refusing_port();
    let address = format!("127.0.0.1:{port}");
    let run = render(d, "96", &["--display-server", &address]);
    run.assert_success();
    one_warning(&run.stderr, &address, "cannot connect");
    let with = std::fs::read(d.join("out.exr")).unwrap();
    render(d, "96", &[]).assert_success();
    assert!(with == std::fs::read(d.join("out.exr")).unwrap());
    // --quiet: not even the warning.
    let run = render(d, "96", &["--quiet", "--display-server", &address]);
    run.assert_success();
    assert_eq!(run.stderr, "");
}

#[test]
fn a_server_that_closes_at_once_is_one_warning_and_tried_ever_less_often() {
    let dir = TempDir::new().unwrap();
    // As an ssh tunnel with no tev behind it: each connection is accepted and closed.
    let tev = FakeTev::new(|_, _| Vec::new());
    let (run, took) = slow_render(dir.path(), &tev.address);
    run.assert_success();
    one_warning(&run.stderr, &tev.address, "the connection was lost");
    // Tried again after 1 s, then 2 s, 4 s, …: attempt k (from 0) comes at least 2^k − 1 s
    // after the first.
    let connections = tev.connections().len();
    let most = (took.as_secs_f64() + 1.0).log2() as usize + 1;
    assert!(
        (2..=most).contains(&connections),
        "{connections} connections in {took:?}"
    );
}

#[test]
fn a_tev_that_never_reads_holds_the_render_up_once_and_is_one_warning() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let tev = deaf_tev();
    // 27 MB of packets: more than the socket buffers hold.
    let args = [
        "render", SCENE, "--width", "1500", "--height", "1500", "--spp", "1", "-o", "out.exr",
    ];
    let run = timbre(
        d,
        &[&args[..], &["--display-server", &tev.address]].concat(),
    );
    run.assert_success();
    one_warning(&run.stderr, &tev.address, "it took no data for 3 s");
    let connections = tev.connections();
    assert!(connections.iter().all(Vec::is_empty));
    let with = std::fs::read(d.join("out.exr")).unwrap();
    let alone = timbre(d, &args);
    alone.assert_success();
    assert!(with == std::fs::read(d.join("out.exr")).unwrap());
    // Held up 3 s a connection (not 3 s a write that made some progress, as it once was: 9 s
    // for one connection), with the render's own time and 3 s more to spare for its ups and
    // downs, however busy the machine is.
    let alone_seconds = reported_seconds(&alone);
    let held = reported_seconds(&run) - alone_seconds;
    let most = 3.0 * connections.len() as f64 + alone_seconds + 3.0;
    assert!(
        held < most,
        "held up {held} s by {} connection(s)",
        connections.len()
    );
}

#[test]
fn a_tev_that_reads_everything_but_never_closes_is_shown_the_image_without_a_warning() {
    let dir = TempDir::new().unwrap();
    // It reads to the end of the stream, then holds its end open until timbre is done: the
    // end of a render does not wait for it to close.
    let mut held = Vec::new();
    let tev = FakeTev::new(move |_, mut stream| {
        let packets = read_packets(&mut stream, usize::MAX);
        held.push(stream);
        packets
    });
    let run = render(dir.path(), "96", &["--display-server", &tev.address]);
    run.assert_success();
    assert_eq!(run.stderr, "");
    let connections = tev.connections();
    assert_eq!(connections.len(), 1);
    assert_shows(&assemble(&connections[0]), &dir.path().join("out.exr"));
}

#[test]
fn a_tev_that_quits_before_the_last_band_is_not_taken_to_have_the_image() {
    let dir = TempDir::new().unwrap();
    // tev reads the image up to its last band (rows 248 to 256), then quits: closes without
    // reading on.
    let tev = FakeTev::new(|_, mut stream| {
        let mut packets = Vec::new();
        while let Some(packet) = read_packets(&mut stream, 1).pop() {
            let end = match &packet {
                Packet::Update { y, height, .. } => y + height,
                Packet::Create { .. } => 0,
            };
            packets.push(packet);
            if end >= 248 {
                break;
            }
        }
        packets
    });
    // Slow enough (a few milliseconds a band) that the connection is made before the end.
    let args = [
        "render",
        SCENE,
        "--width",
        "96",
        "--height",
        "256",
        "--spp",
        "64",
        "--threads",
        "1",
        "-o",
        "out.exr",
        "--display-server",
        &tev.address,
    ];
    let run = timbre(dir.path(), &args);
    run.assert_success();
    one_warning(&run.stderr, &tev.address, "the connection was lost");
    // Not tried again at the end, the attempt having just failed.
    assert_eq!(tev.connections().len(), 1);
}

#[test]
fn the_copy_kept_for_tev_is_in_the_memory_check() {
    if Command::new("prlimit").arg("--version").output().is_err() {
        eprintln!("skipped: no prlimit");
        return;
    }
    let dir = TempDir::new().unwrap();
    let (_held, port) = refusing_port();
    // Under a 1 GB address-space cap an 8192² single view is streamed to its file in little
    // memory (tests/cli.rs), but the copy kept for tev (12 bytes a pixel: 0.75 GiB) does not
    // fit: refused before rendering.
    let mut command = Command::new("prlimit");
    command.arg("--as=1000000000").arg(TIMBRE).args([
        "render",
        SCENE,
        "--width",
        "8192",
        "--height",
        "8192",
        "--threads",
        "1",
        "-o",
        "big.exr",
        "--display-server",
        &format!("127.0.0.1:{port}"),
    ]);
    let run = bounded(dir.path(), command);
    run.assert_bad_input(&["8192x8192 render shown in tev", "needs about"]);
    assert!(!dir.path().join("big.exr").exists());
}

#[test]
fn bad_display_servers_are_refused_with_exit_code_2() {
    let dir = TempDir::new().unwrap();
    for (value, message) in [
        ("nohost", "expected HOST:PORT"),
        ("host:0", "the port must be from 1 to 65535"),
        ("host:65536", "the port must be from 1 to 65535"),
        (":14158", "expected HOST:PORT"),
        ("::1:14158", "brackets"),
    ] {
        let run = render(dir.path(), "96", &["--display-server", value]);
        assert_eq!(run.code, Some(2), "{value}: {}", run.stderr);
        assert!(
            run.stderr.contains("--display-server") && run.stderr.contains(message),
            "{value}: {}",
            run.stderr
        );
    }
    assert!(!dir.path().join("out.exr").exists());
}

#[test]
fn a_stereo_render_is_shown_once_its_views_are_combined() {
    let dir = TempDir::new().unwrap();
    let tev = FakeTev::reading(vec![]);
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/3d-tv-side-by-side.toml"
    );
    let args = [
        "render",
        scene,
        "--set",
        "camera.stereo=\"side-by-side\"",
        "--width",
        "48",
        "--height",
        "32",
        "--spp",
        "1",
        "-o",
        "out.exr",
        "--display-server",
        &tev.address,
    ];
    timbre(dir.path(), &args).assert_success();
    let shown = assemble(&tev.connections()[0]);
    // The packed frame: two views of 48 × 32 side by side.
    assert_eq!(shown.name, "out.exr");
    assert_eq!((shown.width, shown.height), (96, 32));
    assert_shows(&shown, &dir.path().join("out.exr"));
}
