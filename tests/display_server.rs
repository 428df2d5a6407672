//! `timbre render --display-server HOST:PORT`: a fake tev server on the loopback interface
//! reads every packet strictly as tev's IPC protocol lays it out (a u32 length counting
//! itself, a u8 type, then the fields, little-endian; CreateImage = 4, UpdateImage V3 = 6),
//! assembles the image from the updates and checks it against the EXR the render wrote, bit
//! for bit; also after the connection is dropped mid-render, for a part of the image, with no
//! tev at all, and for bad values of the flag. Every wait is bounded.

mod common;

use std::fs::File;
use std::io::{ErrorKind, Read};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::Command;
use std::thread;
use std::time::{Duration, Instant};

use exr::prelude::FlatSamples;
use tempfile::TempDir;

use common::cli::{Run, TIMBRE};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/studio.toml");
/// The longest any wait may take before the test fails.
const LIMIT: Duration = Duration::from_secs(120);
/// tev reads packets into a buffer of 1 MiB (it grows it for larger ones); tiles stay below.
const LARGEST_PACKET: usize = 1 << 20;

/// Runs `timbre` with `args` in `dir`, killing it if it runs longer than [`LIMIT`].
fn timbre(dir: &Path, args: &[&str]) -> Run {
    let out = |name: &str| File::create(dir.join(name)).unwrap();
    let mut child = Command::new(TIMBRE)
        .args(args)
        .current_dir(dir)
        .stdout(out("timbre.stdout"))
        .stderr(out("timbre.stderr"))
        .spawn()
        .expect("run timbre");
    let deadline = Instant::now() + LIMIT;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("timbre {args:?} ran longer than {LIMIT:?}");
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

/// Waits for the next connection to `listener` (non-blocking).
fn accept(listener: &TcpListener) -> TcpStream {
    let deadline = Instant::now() + LIMIT;
    loop {
        match listener.accept() {
            Ok((stream, _)) => {
                stream.set_nonblocking(false).unwrap();
                stream.set_read_timeout(Some(LIMIT)).unwrap();
                return stream;
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock && Instant::now() < deadline => {
                thread::sleep(Duration::from_millis(5));
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

/// A fake tev on a free loopback port: the connections it serves, each read to `limits[i]`
/// packets (`usize::MAX`: to the end) and then closed, on a thread; its port.
fn fake_tev(limits: Vec<usize>) -> (thread::JoinHandle<Vec<Vec<Packet>>>, u16) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    listener.set_nonblocking(true).unwrap();
    let port = listener.local_addr().unwrap().port();
    let server = thread::spawn(move || {
        limits
            .into_iter()
            .map(|limit| read_packets(&mut accept(&listener), limit))
            .collect()
    });
    (server, port)
}

/// A rectangle of pixels: x, y, width, height.
type Rect = (u32, u32, u32, u32);

/// The image tev would show after `packets`: its name and size, and each pixel's R, G, B where
/// an update set it; also the rectangles updated.
struct Shown {
    name: String,
    width: u32,
    height: u32,
    pixels: Vec<Option<[f32; 3]>>,
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
            shown.pixels[(py * shown.width + px) as usize] = Some(*value);
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
/// pixels bit for bit; nothing outside is updated.
#[track_caller]
fn assert_shows(shown: &Shown, path: &Path) {
    let (rgb, (x0, y0, w, h), full) = read_exr(path);
    assert_eq!(shown.name, "out.exr");
    assert_eq!((shown.width, shown.height), full);
    let bits = |c: [f32; 3]| c.map(f32::to_bits);
    for y in 0..shown.height {
        for x in 0..shown.width {
            let got = shown.pixels[(y * shown.width + x) as usize];
            let inside = (x0..x0 + w).contains(&x) && (y0..y0 + h).contains(&y);
            if inside {
                let want = rgb[((y - y0) * w + x - x0) as usize];
                assert_eq!(got.map(bits), Some(bits(want)), "pixel ({x}, {y})");
            } else {
                assert_eq!(got, None, "pixel ({x}, {y}) is outside the part rendered");
            }
        }
    }
}

#[test]
fn tev_is_shown_the_image_the_exr_holds_bit_for_bit() {
    let dir = TempDir::new().unwrap();
    let (server, port) = fake_tev(vec![usize::MAX]);
    let address = format!("127.0.0.1:{port}");
    let run = render(dir.path(), "96", &["--display-server", &address]);
    run.assert_success();
    assert!(!run.stderr.contains("warning"), "{}", run.stderr);
    let connections = server.join().unwrap();
    assert_eq!(connections.len(), 1);
    let shown = assemble(&connections[0]);
    assert_shows(&shown, &dir.path().join("out.exr"));
    // In tiles of at most 128 × 128 pixels.
    assert!(shown.updates.iter().all(|u| u.2 <= 128 && u.3 <= 128));
}

#[test]
fn a_tev_that_restarts_is_sent_the_whole_image_again() {
    let dir = TempDir::new().unwrap();
    // The first connection is dropped after the image is created and one tile is updated;
    // 200 pixels are two tiles across, so at least one tile is then sent or to be sent.
    let (server, port) = fake_tev(vec![2, usize::MAX]);
    let address = format!("127.0.0.1:{port}");
    let run = render(dir.path(), "200", &["--display-server", &address]);
    run.assert_success();
    assert!(
        run.stderr.contains(&format!(
            "timbre: warning: tev at {address}: the connection was lost"
        )),
        "{}",
        run.stderr
    );
    let connections = server.join().unwrap();
    assert!(matches!(
        connections[0][..],
        [Packet::Create { .. }, Packet::Update { .. }]
    ));
    assert_shows(&assemble(&connections[1]), &dir.path().join("out.exr"));
}

#[test]
fn a_part_render_creates_the_whole_image_and_updates_only_its_rectangle() {
    let dir = TempDir::new().unwrap();
    let (server, port) = fake_tev(vec![usize::MAX]);
    let address = format!("127.0.0.1:{port}");
    let bounds = ["--pixel-bounds", "13,90,9,50"];
    let run = render(
        dir.path(),
        "96",
        &[&bounds[..], &["--display-server", &address]].concat(),
    );
    run.assert_success();
    let shown = assemble(&server.join().unwrap()[0]);
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
    // A port nothing listens on: one that was free a moment ago.
    let port = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let address = format!("127.0.0.1:{port}");
    let run = render(d, "96", &["--display-server", &address]);
    run.assert_success();
    let warning = format!("timbre: warning: tev at {address}: cannot connect");
    assert_eq!(run.stderr.matches(&warning).count(), 1, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    let with = std::fs::read(d.join("out.exr")).unwrap();
    render(d, "96", &[]).assert_success();
    assert!(with == std::fs::read(d.join("out.exr")).unwrap());
    // --quiet: not even the warning.
    let run = render(d, "96", &["--quiet", "--display-server", &address]);
    run.assert_success();
    assert_eq!(run.stderr, "");
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
    let (server, port) = fake_tev(vec![usize::MAX]);
    let address = format!("127.0.0.1:{port}");
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
        &address,
    ];
    timbre(dir.path(), &args).assert_success();
    let shown = assemble(&server.join().unwrap()[0]);
    // The packed frame: two views of 48 × 32 side by side.
    assert_eq!((shown.width, shown.height), (96, 32));
    assert_shows(&shown, &dir.path().join("out.exr"));
}
