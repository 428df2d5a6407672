//! `timbre serve` from outside, as a page talks to it: the converged preview against the CLI's
//! render of the same settings (and `--set`), display changes that do not restart the
//! accumulation, located errors that keep the last picture, inspection against the CLI's AOVs,
//! saving, the watched file, trajectories from a pixel; and the server's rules: host names,
//! origins, the token beyond loopback, malformed and oversized messages.

mod common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use common::cli::{HANG, TIMBRE, decode_png, timbre, write};
use futures_util::{SinkExt, StreamExt};
use serde_json::Value;
use tempfile::TempDir;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::protocol::frame::coding::CloseCode;

/// A small studio scene with a glass ball: refraction, shadows and jittered samples.
const SCENE: &str = r#"studio = "lattice"
[render]
width = 48
height = 36
[[object]]
name = "glass ball"
shadow_throwing = false
shape = { type = "sphere", centre = [0, -0.2, 6], radius = 0.6 }
surface = { type = "refractive", index_ratio = 1.5, transmission = 0.96 }
"#;

/// Arguments every server and reference render share: the size comes from the scene.
const SPP: u32 = 3;

/// A running `timbre serve` in a directory of its own, killed when dropped.
struct Server {
    child: Child,
    port: u16,
    /// The address line printed at start.
    line: String,
    /// The directory the server's files are in (removed when the server is dropped).
    _dir: TempDir,
    /// The scene file's directory, in it.
    home: PathBuf,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Server {
    fn start(args: &[&str]) -> Server {
        Server::start_with(SCENE, args)
    }

    /// A server of `scene` (written to scene.toml in a directory of its own).
    fn start_with(scene: &str, args: &[&str]) -> Server {
        Server::start_in(TempDir::new().unwrap(), ".", scene, args)
    }

    /// A server of `scene`, written to `dir/folder/scene.toml`, in that folder.
    fn start_in(dir: TempDir, folder: &str, scene: &str, args: &[&str]) -> Server {
        let home = dir.path().join(folder);
        write(&home, "scene.toml", scene);
        let mut child = Command::new(TIMBRE)
            .args(["serve", "scene.toml", "--port", "0", "--threads", "2"])
            .args(["--spp", &SPP.to_string()])
            .args(args)
            .current_dir(&home)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start timbre serve");
        let (port, line) = common::cli::served_port(&mut child);
        Server {
            child,
            port,
            line,
            _dir: dir,
            home,
        }
    }

    /// The preview engines running in the server: their file watchers (threads named
    /// `timbre-watch`; the engine's own thread names the render threads it starts after it).
    fn engines(&self) -> usize {
        let tasks = format!("/proc/{}/task", self.child.id());
        std::fs::read_dir(tasks)
            .unwrap()
            .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("comm")).ok())
            .filter(|name| name.trim() == "timbre-watch")
            .count()
    }

    /// The scene file's directory.
    fn path(&self) -> &Path {
        &self.home
    }

    /// The scene file's text on disk.
    fn scene_file(&self) -> String {
        std::fs::read_to_string(self.path().join("scene.toml")).unwrap()
    }

    /// The CLI's render of the scene file as it is now, with the same size and samples.
    fn reference(&self, set: &[&str]) -> image::RgbImage {
        let mut args = vec!["render", "scene.toml", "-q", "--spp", "3", "-o", "ref.png"];
        for s in set {
            args.extend(["--set", s]);
        }
        timbre(self.path(), &args).assert_success();
        decode_png(&self.path().join("ref.png"))
    }

    async fn connect(&self) -> Page {
        self.connect_with(&[], "").await.expect("connect")
    }

    async fn connect_with(
        &self,
        headers: &[(&str, &str)],
        query: &str,
    ) -> Result<Page, tokio_tungstenite::tungstenite::Error> {
        let mut request = format!("ws://127.0.0.1:{}/ws{query}", self.port)
            .into_client_request()
            .unwrap();
        for (name, value) in headers {
            let name: tokio_tungstenite::tungstenite::http::HeaderName = name.parse().unwrap();
            request.headers_mut().insert(name, value.parse().unwrap());
        }
        let (socket, _) = tokio_tungstenite::connect_async(request).await?;
        Ok(Page { socket, last: None })
    }

    /// The status line and body of a plain HTTP GET of `target` with this Host header.
    fn get(&self, target: &str, host: &str) -> (u16, String) {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream.set_read_timeout(Some(HANG)).unwrap();
        write!(
            stream,
            "GET {target} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
        )
        .unwrap();
        let mut response = String::new();
        stream.read_to_string(&mut response).unwrap();
        let status = response
            .split(' ')
            .nth(1)
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no status in {response:?}"));
        (status, response)
    }
}

/// A frame: its header and RGBA pixels.
#[derive(Debug, Clone)]
struct Frame {
    generation: u32,
    done: u32,
    target: u32,
    width: u32,
    height: u32,
    rgba: Vec<u8>,
}

impl Frame {
    fn parse(bytes: &[u8]) -> Frame {
        let at = |k: usize| u32::from_le_bytes(bytes[4 * k..4 * k + 4].try_into().unwrap());
        let frame = Frame {
            generation: at(0),
            done: at(1),
            target: at(2),
            width: at(3),
            height: at(4),
            rgba: bytes[20..].to_vec(),
        };
        assert_eq!(frame.rgba.len(), 4 * (frame.width * frame.height) as usize);
        frame
    }

    /// The number of pixels whose RGB differs from `image`'s.
    fn differences(&self, image: &image::RgbImage) -> usize {
        assert_eq!((self.width, self.height), image.dimensions());
        self.rgba
            .chunks_exact(4)
            .zip(image.pixels())
            .filter(|(a, b)| a[..3] != b.0)
            .count()
    }
}

enum Received {
    Json(Value),
    Frame(Frame),
}

struct Page {
    socket: tokio_tungstenite::WebSocketStream<
        tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>,
    >,
    /// The last frame received (the server sends only the newest frame, and no frame again:
    /// a frame passed over while waiting for a message may be the last of its picture).
    last: Option<Frame>,
}

impl Page {
    async fn send(&mut self, message: Value) {
        self.socket
            .send(Message::Text(message.to_string().into()))
            .await
            .unwrap();
    }

    async fn next(&mut self) -> Option<Received> {
        loop {
            let m = tokio::time::timeout(HANG, self.socket.next())
                .await
                .expect("a message in time")?;
            match m.ok()? {
                Message::Text(t) => return Some(Received::Json(serde_json::from_str(&t).unwrap())),
                Message::Binary(b) => {
                    let frame = Frame::parse(&b);
                    self.last = Some(frame.clone());
                    return Some(Received::Frame(frame));
                }
                Message::Close(_) => return None,
                _ => {}
            }
        }
    }

    /// The first JSON message of this `type` (frames and others are skipped).
    async fn json(&mut self, kind: &str) -> Value {
        loop {
            match self.next().await.expect("the connection stays open") {
                Received::Json(v) if v["type"] == kind => return v,
                _ => {}
            }
        }
    }

    /// The next notice, which must be an error or not as `error` says, with a message
    /// containing `text`.
    async fn notice(&mut self, error: bool, text: &str) -> Value {
        let notice = self.json("notice").await;
        assert!(
            notice["error"] == error
                && notice["message"].as_str().is_some_and(|m| m.contains(text)),
            "a notice (error: {error}) containing {text:?}: {notice}"
        );
        notice
    }

    /// The next error, whose message must contain `text`.
    async fn error(&mut self, text: &str) -> Value {
        let error = self.json("error").await;
        assert!(
            error["message"].as_str().is_some_and(|m| m.contains(text)),
            "an error containing {text:?}: {error}"
        );
        error
    }

    /// Frames until one satisfies `done`; all frames seen, that one last.
    async fn frames_until(&mut self, done: impl Fn(&Frame) -> bool) -> Vec<Frame> {
        let mut seen = Vec::new();
        loop {
            if let Received::Frame(f) = self.next().await.expect("the connection stays open") {
                let stop = done(&f);
                seen.push(f);
                if stop {
                    return seen;
                }
            }
        }
    }

    /// The first frame with every sample, of a generation after `after` (perhaps one already
    /// received).
    async fn converged(&mut self, after: u32) -> Frame {
        let done = |f: &Frame| f.generation > after && f.done == f.target;
        if let Some(f) = self.last.clone().filter(done) {
            return f;
        }
        self.frames_until(done).await.pop().unwrap()
    }

    /// How the server closed the connection: the close code, or none if it just dropped it.
    async fn closed(&mut self) -> Option<CloseCode> {
        loop {
            let m = tokio::time::timeout(HANG, self.socket.next())
                .await
                .expect("closed in time");
            match m {
                Some(Ok(Message::Close(frame))) => return frame.map(|f| f.code),
                Some(Ok(_)) => {}
                Some(Err(_)) | None => return None,
            }
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_converged_preview_is_the_cli_render_and_a_set_restarts_it() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    let state = page.json("scene").await;
    assert_eq!(
        (state["width"].as_u64(), state["spp"].as_u64()),
        (Some(48), Some(3))
    );
    let first = page.converged(0).await;
    assert_eq!(first.target, SPP);
    // Exactly: the preview adds the same samples' exact sums as the CLI and converts to 8 bits
    // as the PNG writer does.
    assert_eq!(first.differences(&server.reference(&[])), 0);

    let set = "camera.position=[0.2, 0.1, 0]";
    page.send(serde_json::json!({"type": "set", "set": [set]}))
        .await;
    let frames = page
        .frames_until(|f| f.generation > first.generation && f.done == f.target)
        .await;
    let fresh: Vec<&Frame> = frames
        .iter()
        .filter(|f| f.generation > first.generation)
        .collect();
    assert_eq!(
        fresh[0].done, 0,
        "the accumulation restarts with a coarse frame"
    );
    let last = fresh.last().unwrap();
    let moved = server.reference(&[set]);
    assert_eq!(last.differences(&moved), 0);
    assert!(first.differences(&moved) > 100, "the camera moved");

    // Values the file leaves at their defaults are parameters too: the camera's velocity.
    let listed = |state: &Value, key: &str| {
        state["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["key"] == key)
            .map(|p| p["value"].clone())
    };
    assert_eq!(
        listed(&state, "camera.beta"),
        Some(serde_json::json!([0.0, 0.0, 0.0]))
    );
    assert_eq!(listed(&state, "render.seed"), Some(serde_json::json!(0)));
    let beta = "camera.beta=[0, 0, 0.6]";
    page.send(serde_json::json!({"type": "set", "set": [beta]}))
        .await;
    let state = page.json("scene").await;
    assert_eq!(
        listed(&state, "camera.beta"),
        Some(serde_json::json!([0, 0, 0.6]))
    );
    let fast = page.converged(last.generation).await;
    assert_eq!(fast.differences(&server.reference(&[set, beta])), 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn exposure_changes_the_display_but_not_the_accumulation() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    let before = page.converged(0).await;
    page.send(serde_json::json!({"type": "exposure", "stops": 1}))
        .await;
    let after = page
        .frames_until(|f| f.generation == before.generation)
        .await
        .pop()
        .unwrap();
    assert_eq!(
        (after.done, after.target),
        (SPP, SPP),
        "no samples were thrown away"
    );
    // Twice the light, clamped: each channel is at least what it was, and those not clamped
    // are twice as bright, to the rounding of 8 bits.
    for (b, a) in before.rgba.iter().zip(&after.rgba) {
        let want = (2 * *b as i32).min(255);
        assert!((*a as i32 - want).abs() <= 1, "{b} -> {a}");
    }
}

/// The scene's `[render] exposure` is where the display starts: the page is told it, and the
/// frames are the unexposed ones doubled (to the rounding of 8 bits) for `exposure = 1`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_scenes_exposure_is_where_the_display_starts() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    let plain = page.converged(0).await;
    let exposed = SCENE.replace("width = 48", "width = 48\nexposure = 1");
    assert_ne!(exposed, SCENE);
    page.send(serde_json::json!({"type": "text", "text": exposed}))
        .await;
    let state = page.json("scene").await;
    assert_eq!(state["exposure"], 1.0, "{state}");
    let after = page.converged(plain.generation).await;
    for (b, a) in plain.rgba.iter().zip(&after.rgba) {
        let want = (2 * *b as i32).min(255);
        assert!((*a as i32 - want).abs() <= 1, "{b} -> {a}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_error_in_the_text_is_located_and_the_last_picture_stays() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    let good = page.converged(0).await;
    let broken = SCENE.replace("width = 48", "width = = 48");
    page.send(serde_json::json!({"type": "text", "text": broken}))
        .await;
    let error = page.json("error").await;
    assert_eq!(error["line"], 3, "{error}");
    assert!(error["column"].as_u64().is_some_and(|c| c >= 1), "{error}");
    assert_eq!(error["text"], broken.as_str());
    // A page that connects now still gets the last good picture.
    let mut late = server.connect().await;
    let Some(Received::Json(state)) = late.next().await else {
        panic!("a late page gets the last good scene first")
    };
    assert_eq!(state["type"], "scene", "{state}");
    let error_again = late.json("error").await;
    assert_eq!(error_again["line"], 3);
    let frame = late.frames_until(|_| true).await.pop().unwrap();
    assert_eq!(frame.rgba, good.rgba);
    // Fixing the text renders again.
    page.send(serde_json::json!({"type": "text", "text": SCENE.replace("0.6", "0.4")}))
        .await;
    let fixed = page.converged(good.generation).await;
    assert_ne!(fixed.rgba, good.rgba);
}

/// While the text has an error, a move still moves: the picture becomes the last good scene
/// with the move (the CLI's render of the scene file with that --set), the page gets that
/// scene and then the text's error again.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn moves_go_on_while_the_text_has_an_error() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    let good = page.converged(0).await;
    let broken = SCENE.replace("width = 48", "width = = 48");
    page.send(serde_json::json!({"type": "text", "text": broken}))
        .await;
    assert_eq!(page.json("error").await["line"], 3);
    let set = "camera.position=[0.2, 0.1, 0]";
    page.send(serde_json::json!({"type": "set", "set": [set]}))
        .await;
    let state = page.json("scene").await;
    assert!(
        state["overrides"].to_string().contains("camera.position"),
        "{state}"
    );
    let error = page.json("error").await;
    assert_eq!(
        (error["line"].as_u64(), error["text"].as_str()),
        (Some(3), Some(broken.as_str()))
    );
    let moved = page.converged(good.generation).await;
    assert_eq!(moved.differences(&server.reference(&[set])), 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn inspecting_a_pixel_finds_what_the_cli_aovs_record() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    page.converged(0).await;
    timbre(
        server.path(),
        &[
            "render",
            "scene.toml",
            "-q",
            "--spp",
            "1",
            "--aov",
            "depth,object",
            "-o",
            "aov.exr",
        ],
    )
    .assert_success();
    let image =
        exr::prelude::read_all_flat_layers_from_file(server.path().join("aov.exr")).unwrap();
    let layer = &image.layer_data[0];
    let channel = |name: &str| -> Vec<f32> {
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .unwrap();
        match &c.sample_data {
            exr::prelude::FlatSamples::F32(v) => v.clone(),
            _ => panic!("f32"),
        }
    };
    let (depth, object) = (channel("depth.Z"), channel("object.id"));
    // The ball's centre, the floor, the sky.
    for (x, y) in [(24, 19), (5, 33), (2, 1)] {
        page.send(serde_json::json!({"type": "inspect", "x": x, "y": y}))
            .await;
        let found = page.json("inspection").await;
        let k = y * 48 + x;
        let hit = &found["hit"];
        assert_eq!(hit["id"].as_f64().unwrap() as f32, object[k], "{found}");
        let distance = hit["distance"].as_f64().unwrap();
        assert!(
            (distance as f32 - depth[k]).abs() <= 1e-5 * depth[k],
            "{distance} vs {}",
            depth[k]
        );
    }
    page.send(serde_json::json!({"type": "inspect", "x": 24, "y": 19}))
        .await;
    let ball = page.json("inspection").await;
    assert_eq!(ball["hit"]["object"], "glass ball");
    assert_eq!(ball["hit"]["surface"], "refractive");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn saving_renders_the_converged_picture_beside_the_scene_file() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    page.converged(0).await;
    page.send(serde_json::json!({"type": "save", "file": "saved.png"}))
        .await;
    page.notice(false, "saved").await;
    let saved = decode_png(&server.path().join("saved.png"));
    assert_eq!(saved, server.reference(&[]));
    for bad in [
        "../escape.png",
        "/tmp/x.png",
        ".hidden.png",
        "picture.jpg",
        "",
    ] {
        page.send(serde_json::json!({"type": "save", "file": bad}))
            .await;
        let refused = page.json("notice").await;
        assert_eq!(refused["error"], true, "{bad}: {refused}");
    }
    assert!(!server.path().join("../escape.png").exists());
    // Never through a link: a name that is a link to elsewhere is refused.
    let elsewhere = TempDir::new().unwrap();
    let target = elsewhere.path().join("precious.txt");
    std::fs::write(&target, "keep me").unwrap();
    std::os::unix::fs::symlink(&target, server.path().join("link.png")).unwrap();
    page.send(serde_json::json!({"type": "save", "file": "link.png"}))
        .await;
    page.notice(true, "not a plain file").await;
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep me");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_scene_file_is_watched_and_trajectories_join_the_text() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    let first = page.json("scene").await;
    let edited = SCENE.replace("radius = 0.6", "radius = 0.5");
    std::fs::write(server.path().join("scene.toml"), &edited).unwrap();
    let reloaded = page.json("scene").await;
    assert_eq!(reloaded["text"], edited.as_str());
    assert!(reloaded["generation"].as_u64() > first["generation"].as_u64());

    page.send(serde_json::json!({"type": "trajectory", "x": 24, "y": 19}))
        .await;
    let with_ray = page.json("scene").await;
    let text = with_ray["text"].as_str().unwrap();
    assert!(text.starts_with(&edited));
    assert!(
        text.contains("[[ray_trajectory]]\nname = \"pixel 24,19\""),
        "{text}"
    );
    // Written back only when asked.
    assert_eq!(server.scene_file(), edited);
    page.send(serde_json::json!({"type": "write_scene"})).await;
    page.json("notice").await;
    assert_eq!(server.scene_file(), text);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_loopback_server_refuses_other_host_names_and_other_sites_pages() {
    let server = Server::start(&[]);
    assert!(!server.line.contains("token"), "{}", server.line);
    let port = server.port;
    let (status, body) = server.get("/", &format!("127.0.0.1:{port}"));
    assert_eq!(status, 200);
    assert!(body.contains("<canvas"), "the page");
    assert_eq!(server.get("/", &format!("localhost:{port}")).0, 200);
    // DNS rebinding: another site's name pointing at 127.0.0.1.
    assert_eq!(server.get("/", &format!("evil.example:{port}")).0, 403);
    assert_eq!(
        server
            .get("/../../etc/passwd", &format!("127.0.0.1:{port}"))
            .0,
        404
    );
    // Another site's page may not open the WebSocket; the server's own may.
    let origin = format!("http://127.0.0.1:{port}");
    assert!(
        server
            .connect_with(&[("origin", "http://evil.example")], "")
            .await
            .is_err()
    );
    let mut own = server
        .connect_with(&[("origin", &origin)], "")
        .await
        .unwrap();
    own.json("scene").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_server_beyond_loopback_needs_the_printed_token() {
    let server = Server::start(&["--bind", "0.0.0.0"]);
    let token = server
        .line
        .split("?token=")
        .nth(1)
        .map(str::trim)
        .unwrap_or_else(|| panic!("no token in {:?}", server.line));
    assert_eq!(token.len(), 32);
    assert!(token.chars().all(|c| c.is_ascii_hexdigit()));
    let host = format!("127.0.0.1:{}", server.port);
    assert_eq!(server.get("/", &host).0, 403);
    assert_eq!(server.get("/?token=0123", &host).0, 403);
    let wrong = format!("/?token={}", "0".repeat(32));
    assert_eq!(server.get(&wrong, &host).0, 403);
    assert_eq!(server.get(&format!("/?token={token}"), &host).0, 200);
    assert!(server.connect_with(&[], "").await.is_err());
    let mut page = server
        .connect_with(&[], &format!("?token={token}"))
        .await
        .unwrap();
    page.json("scene").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn malformed_and_oversized_messages_close_their_own_connection_only() {
    let server = Server::start(&[]);
    let mut watcher = server.connect().await;
    watcher.json("scene").await;
    let cases: Vec<(Message, Option<CloseCode>)> = vec![
        (Message::Text("not json".into()), Some(CloseCode::Policy)),
        (
            Message::Text(r#"{"type":"format_disk"}"#.into()),
            Some(CloseCode::Policy),
        ),
        (
            Message::Text(r#"{"type":"inspect","x":1}"#.into()),
            Some(CloseCode::Policy),
        ),
        // Unknown fields, also of the messages that have none.
        (
            Message::Text(r#"{"type":"write_scene","evil":1}"#.into()),
            Some(CloseCode::Policy),
        ),
        (
            Message::Text(r#"{"type":"cancel_save","evil":1}"#.into()),
            Some(CloseCode::Policy),
        ),
        (
            Message::Binary(vec![1, 2, 3].into()),
            Some(CloseCode::Unsupported),
        ),
        // Over the 4 MiB limit: the connection is dropped (or closed as too big).
        (Message::Text("x".repeat(5 << 20).into()), None),
    ];
    for (message, code) in cases {
        let mut page = server.connect().await;
        page.json("scene").await;
        let _ = page.socket.send(message).await;
        let got = page.closed().await;
        if code.is_some() {
            assert_eq!(got, code);
        }
    }
    // A value the scene cannot take is the user's error: a notice, and the page stays.
    let mut page = server.connect().await;
    page.send(serde_json::json!({"type": "set", "set": ["no equals sign"]}))
        .await;
    page.notice(true, "key=value").await;
    // Numbers are echoed in short.
    page.send(serde_json::json!({"type": "exposure", "stops": 1e308}))
        .await;
    let notice = page.notice(true, "exposure").await;
    assert_eq!(notice["message"], "exposure 1e308: from -30 to 30 stops");
    // The server and its other pages go on.
    watcher
        .send(serde_json::json!({"type": "set", "set": ["render.seed=7"]}))
        .await;
    watcher.json("scene").await;
    server.connect().await.json("scene").await;
}

#[test]
fn a_missing_scene_or_a_busy_port_is_a_clear_error() {
    let dir = TempDir::new().unwrap();
    let missing = timbre(dir.path(), &["serve", "nothing.toml", "--port", "0"]);
    missing.assert_bad_input(&["nothing.toml"]);
    let server = Server::start(&[]);
    write(dir.path(), "scene.toml", SCENE);
    let busy = timbre(
        dir.path(),
        &["serve", "scene.toml", "--port", &server.port.to_string()],
    );
    busy.assert_bad_input(&["cannot listen on 127.0.0.1:", "in use"]);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_page_may_name_only_the_scenes_own_files() {
    let server = Server::start(&[]);
    write(
        server.path(),
        "part.toml",
        "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 8], radius = 0.3 }\nsurface = { type = \"coloured\", diffuse = [1, 0, 0] }\n",
    );
    let mut page = server.connect().await;
    page.json("scene").await;
    for outside in ["/etc/hostname", "../part.toml", "sub/../../part.toml"] {
        let text = format!("{SCENE}\n[[include]]\nfile = \"{outside}\"\n");
        page.send(serde_json::json!({"type": "text", "text": text}))
            .await;
        page.error("only files in the scene file's directory").await;
    }
    // Through --set too.
    page.send(serde_json::json!({"type": "text", "text": format!("{SCENE}\n[[include]]\nfile = \"part.toml\"\n")}))
        .await;
    page.json("scene").await;
    page.send(serde_json::json!({"type": "set", "set": ["include.0.file=\"/etc/hostname\""]}))
        .await;
    page.error("only files").await;
    // Nor can such a text be written into the scene file (which is read unchecked).
    let before = server.scene_file();
    let text = format!("{SCENE}\n[[include]]\nfile = \"/etc/hostname\"\n");
    page.send(serde_json::json!({"type": "text", "text": text}))
        .await;
    page.json("error").await;
    page.send(serde_json::json!({"type": "write_scene"})).await;
    page.notice(true, "only files").await;
    assert_eq!(server.scene_file(), before);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_preview_too_large_is_refused_and_the_server_goes_on() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    let first = page.converged(0).await;
    page.send(
        serde_json::json!({"type": "set", "set": ["render.width=2000000", "render.height=400"]}),
    )
    .await;
    page.error("larger than the limit").await;
    page.send(serde_json::json!({"type": "unset", "keys": []}))
        .await;
    let again = page.converged(first.generation).await;
    assert_eq!(again.rgba, first.rgba);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_packed_stereo_frame_is_inspected_in_each_eyes_own_view() {
    let server = Server::start(&["--set", "camera.stereo=\"side-by-side\""]);
    let mut page = server.connect().await;
    let frame = page.converged(0).await;
    assert_eq!(
        (frame.width, frame.height),
        (96, 36),
        "two views side by side"
    );
    // The ball's centre in the left view and in the right view (x from the right view's edge).
    for x in [24, 48 + 24] {
        page.send(serde_json::json!({"type": "inspect", "x": x, "y": 19}))
            .await;
        let found = page.json("inspection").await;
        assert_eq!(found["hit"]["object"], "glass ball", "x = {x}: {found}");
    }
    page.send(serde_json::json!({"type": "inspect", "x": 96, "y": 19}))
        .await;
    let outside = page.json("inspection").await;
    assert!(outside["hit"].is_null(), "{outside}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_scene_files_own_names_stay_usable_while_the_page_changes_it() {
    // The scene file (the user's own) includes a file elsewhere: the page may still move the
    // camera, but not name another file elsewhere.
    let shared = TempDir::new().unwrap();
    let part = write(
        shared.path(),
        "part.toml",
        "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 8], radius = 0.3 }\nsurface = { type = \"coloured\", diffuse = [1, 0, 0] }\n",
    );
    let other = write(shared.path(), "other.toml", "");
    let scene = format!(
        "{SCENE}\n[[include]]\nfile = {:?}\n",
        part.to_str().unwrap()
    );
    let server = Server::start_with(&scene, &[]);
    let mut page = server.connect().await;
    page.json("scene").await;
    page.send(serde_json::json!({"type": "set", "set": ["camera.position=[0.1, 0, 0]"]}))
        .await;
    let moved = page.json("scene").await;
    assert_eq!(moved["overrides"][0], "camera.position=[0.1, 0, 0]");
    let elsewhere = format!("include.0.file={:?}", other.to_str().unwrap());
    page.send(serde_json::json!({"type": "set", "set": [elsewhere]}))
        .await;
    page.error("only files").await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn requests_answer_for_the_scene_as_changed_before_them_and_no_ops_keep_the_samples() {
    let server = Server::start(&[]);
    let mut page = server.connect().await;
    let first = page.converged(0).await;
    // Changes are taken before requests: a save right after a --set saves the changed scene.
    let set = "object.0.surface.index_ratio=1.2";
    page.send(serde_json::json!({"type": "set", "set": [set]}))
        .await;
    page.send(serde_json::json!({"type": "save", "file": "after.png"}))
        .await;
    let saved = page.json("notice").await;
    assert_eq!(saved["error"], false, "{saved}");
    let reference = server.reference(&[set]);
    assert_eq!(decode_png(&server.path().join("after.png")), reference);
    // (A page that connects now gets the newest frame: this one may have passed it already.)
    let mut page = server.connect().await;
    let changed = page.converged(first.generation).await;
    // Nothing to reset, the same value again, the same text again: no new scene (the reply
    // to the inspection, asked after them, comes with no scene before it), samples kept.
    page.send(serde_json::json!({"type": "unset", "keys": ["camera.position"]}))
        .await;
    page.send(serde_json::json!({"type": "set", "set": [set]}))
        .await;
    page.send(serde_json::json!({"type": "inspect", "x": 1, "y": 1}))
        .await;
    loop {
        match page.next().await.expect("open") {
            Received::Json(v) if v["type"] == "inspection" => break,
            Received::Json(v) => assert_ne!(v["type"], "scene", "{v}"),
            Received::Frame(f) => assert_eq!(f.generation, changed.generation),
        }
    }
    // A scene that does not load is not saved.
    page.send(serde_json::json!({"type": "text", "text": "studio = = 1"}))
        .await;
    page.json("error").await;
    page.send(serde_json::json!({"type": "save", "file": "broken.png"}))
        .await;
    page.notice(true, "does not load").await;
    assert!(!server.path().join("broken.png").exists());
}

/// A first key that only a file outside the scene's folder has: no message may show it.
const SECRET: &str = "secret_key_xyz";

/// A sphere, as the text of an included file.
const PART: &str = "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 8], radius = 0.3 }\nsurface = { type = \"coloured\", diffuse = [1, 0, 0] }\n";

/// A server of [`SCENE`] in a folder of a directory that holds outside.toml (its first key
/// [`SECRET`]) and outside.obj; the folder has part.toml and, in sub/, files whose includes
/// reach out: chain.toml (`../../outside.toml`), linked.toml (`up/outside.toml`, sub/up being
/// a link to the directory) and mesh.toml (an object of the mesh `../../outside.obj`), and
/// inside.toml, whose include (`../part.toml`) stays in the folder.
fn server_beside_outside_files() -> Server {
    let dir = TempDir::new().unwrap();
    write(dir.path(), "outside.toml", format!("{SECRET} = 1\n"));
    write(dir.path(), "outside.obj", format!("{SECRET}\nv 0 0 0\n"));
    let sub = dir.path().join("folder/sub");
    write(dir.path(), "folder/part.toml", PART);
    let include = |file: &str| format!("[[include]]\nfile = \"{file}\"\n");
    write(&sub, "chain.toml", include("../../outside.toml"));
    write(&sub, "linked.toml", include("up/outside.toml"));
    std::os::unix::fs::symlink(dir.path(), sub.join("up")).unwrap();
    write(
        &sub,
        "mesh.toml",
        "[[object]]\nshape = { type = \"mesh\", file = \"../../outside.obj\" }\nsurface = { type = \"coloured\", diffuse = [1, 0, 0] }\n",
    );
    write(&sub, "inside.toml", include("../part.toml"));
    Server::start_in(dir, "folder", SCENE, &[])
}

impl Page {
    /// Every JSON message up to the next error or scene, which is returned; none of them may
    /// show [`SECRET`].
    async fn outcome(&mut self) -> Value {
        loop {
            if let Received::Json(v) = self.next().await.expect("the connection stays open") {
                assert!(!v.to_string().contains(SECRET), "{v}");
                if v["type"] == "error" || v["type"] == "scene" {
                    return v;
                }
            }
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn files_that_page_text_reaches_through_includes_must_be_in_the_folder() {
    let server = server_beside_outside_files();
    let mut page = server.connect().await;
    page.json("scene").await;
    // An include of an include inside the folder (through `..`) is fine.
    let with = |file: &str| format!("{SCENE}\n[[include]]\nfile = \"{file}\"\n");
    page.send(serde_json::json!({"type": "text", "text": with("sub/inside.toml")}))
        .await;
    assert_eq!(page.outcome().await["type"], "scene");
    for (file, refused) in [
        ("sub/chain.toml", "../../outside.toml"),
        ("sub/linked.toml", "up/outside.toml"),
        ("sub/mesh.toml", "../../outside.obj"),
    ] {
        page.send(serde_json::json!({"type": "text", "text": with(file)}))
            .await;
        let error = page.outcome().await;
        let message = error["message"].as_str().unwrap_or_default();
        assert!(
            message.contains(&format!("'{refused}'"))
                && message.contains("only files in the scene file's directory"),
            "{file}: {error}"
        );
        // Its line is in the included file, not in the page's text.
        assert!(error["line"].is_null(), "{error}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn page_text_whose_includes_reach_out_of_the_folder_is_not_written() {
    let server = server_beside_outside_files();
    let mut page = server.connect().await;
    page.json("scene").await;
    let text = format!("{SCENE}\n[[include]]\nfile = \"sub/chain.toml\"\n");
    page.send(serde_json::json!({"type": "text", "text": text}))
        .await;
    assert_eq!(page.outcome().await["type"], "error");
    page.send(serde_json::json!({"type": "write_scene"})).await;
    let notice = page.notice(true, "'../../outside.toml'").await;
    assert!(!notice.to_string().contains(SECRET), "{notice}");
    assert_eq!(server.scene_file(), SCENE);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn what_the_users_own_include_reaches_stays_usable_when_the_page_edits_the_text() {
    // The scene file includes a file elsewhere, which includes another beside it.
    let shared = TempDir::new().unwrap();
    write(shared.path(), "inner.toml", PART);
    let part = write(
        shared.path(),
        "part.toml",
        "[[include]]\nfile = \"inner.toml\"\n",
    );
    let scene = format!(
        "{SCENE}\n[[include]]\nfile = {:?}\n",
        part.to_str().unwrap()
    );
    let server = Server::start_with(&scene, &[]);
    let mut page = server.connect().await;
    page.json("scene").await;
    let edited = scene.replace("radius = 0.6", "radius = 0.5");
    page.send(serde_json::json!({"type": "text", "text": edited}))
        .await;
    let state = page.outcome().await;
    assert_eq!(state["type"], "scene", "{state}");
    assert_eq!(state["text"], edited.as_str());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_public_server_gives_each_visitor_their_own_view_and_says_when_it_is_busy() {
    let server = Server::start(&["--public", "--visitors", "2"]);
    let mut a = server.connect().await;
    let mut b = server.connect().await;
    let state = a.json("scene").await;
    // A visitor sees the scene file's name, not where it is on the server.
    assert_eq!(state["path"], "scene.toml");
    assert_eq!(state["public"], true);
    b.json("scene").await;
    let set = "object.0.surface.index_ratio=1.2";
    a.send(serde_json::json!({"type": "set", "set": [set]}))
        .await;
    let changed = a.json("scene").await;
    assert_eq!(changed["overrides"], serde_json::json!([set]));
    // Each converges to the CLI's render of their own changes: A's with the --set, B's without.
    let a_frame = a
        .converged(changed["generation"].as_u64().unwrap() as u32 - 1)
        .await;
    assert_eq!(a_frame.differences(&server.reference(&[set])), 0);
    let b_frame = b.converged(0).await;
    assert_eq!(b_frame.differences(&server.reference(&[])), 0);

    // Each visitor has an engine of their own.
    assert_eq!(server.engines(), 2);
    // A third visitor is told the server is busy, and the connection closes.
    let mut c = server.connect().await;
    let busy = c.json("busy").await;
    assert!(
        busy["message"]
            .as_str()
            .unwrap()
            .contains("2 visitors at once"),
        "{busy}"
    );
    assert_eq!(c.closed().await, Some(CloseCode::Again));
    // Once a visitor leaves, their engine ends, and another visitor is served (in the place
    // that the engine's thread frees as it ends).
    drop(a);
    let deadline = std::time::Instant::now() + HANG;
    while server.engines() != 1 {
        assert!(
            std::time::Instant::now() < deadline,
            "the visitor's engine ends"
        );
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    loop {
        let mut d = server.connect().await;
        // A new engine may send its state or a frame before the scene, as it gets to them.
        let served = loop {
            match d.next().await {
                Some(Received::Json(v)) if v["type"] == "scene" => break true,
                Some(Received::Json(v)) if v["type"] == "busy" => break false,
                Some(_) => {}
                None => panic!("the connection closed before a scene or busy"),
            }
        };
        if served {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the visitor's place is freed"
        );
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_public_server_reads_and_writes_no_file_for_its_pages() {
    let server = Server::start(&["--public"]);
    write(
        server.path(),
        "part.toml",
        "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 8], radius = 0.3 }\nsurface = { type = \"coloured\", diffuse = [1, 0, 0] }\n",
    );
    write(
        server.path(),
        "part.obj",
        "v 0 0 8\nv 1 0 8\nv 0 1 8\nf 1 2 3\n",
    );
    let before = std::fs::read_dir(server.path()).unwrap().count();
    let mut page = server.connect().await;
    page.json("scene").await;
    // No saving, no writing the scene file.
    page.send(serde_json::json!({"type": "save", "file": "render.png"}))
        .await;
    page.notice(true, "a public server writes no files").await;
    page.send(serde_json::json!({"type": "write_scene"})).await;
    page.notice(true, "a public server writes no files").await;
    // No file that the page names, even beside the scene file, by text or by --set.
    for name in ["part.toml", "/etc/hostname"] {
        let text = format!("{SCENE}\n[[include]]\nfile = \"{name}\"\n");
        page.send(serde_json::json!({"type": "text", "text": text}))
            .await;
        page.error("a public server reads no file that its pages name")
            .await;
    }
    page.send(serde_json::json!({"type": "text", "text": SCENE}))
        .await;
    page.json("scene").await;
    let mesh = "object.0.shape={ type = \"mesh\", file = \"part.obj\" }";
    page.send(serde_json::json!({"type": "set", "set": [mesh]}))
        .await;
    page.error("a public server reads no file that its pages name")
        .await;
    page.send(serde_json::json!({"type": "unset", "keys": []}))
        .await;
    page.json("scene").await;
    // A preview larger than a visitor's share is refused.
    page.send(
        serde_json::json!({"type": "set", "set": ["render.width=2048", "render.height=1024"]}),
    )
    .await;
    page.error("public server's limit").await;
    // Hostile messages close the page's own connection, and the server goes on.
    page.send(serde_json::json!({"type": "format_disk"})).await;
    assert_eq!(page.closed().await, Some(CloseCode::Policy));
    let mut again = server.connect().await;
    again.json("scene").await;
    assert_eq!(std::fs::read_dir(server.path()).unwrap().count(), before);
    // Any host name, and any site may embed the page.
    let (status, response) = server.get("/", "timbre.example.org");
    assert_eq!(status, 200, "{response}");
    assert!(response.contains("frame-ancestors *"), "{response}");
}

/// A scene with an `[animation]` gets a frame slider: frame k of the movie is the scene with
/// each track's value at k given by `--set`, byte for byte (the camera keyed linearly from
/// (0, 0, 0) at frame 0 to (0.4, 0.2, 0) at frame 4 is at (0.3, 0.15, 0) at frame 3); a frame
/// past the end shows the last; `null` the scene as written.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_frame_slider_shows_the_movies_frames() {
    let movie = format!(
        "{SCENE}[animation]\nframes = 5\n[[animation.track]]\nkey = \"camera.position\"\n\
         keyframes = [{{ frame = 0, value = [0, 0, 0] }}, {{ frame = 4, value = [0.4, 0.2, 0] }}]\n"
    );
    let server = Server::start_with(&movie, &[]);
    write(server.path(), "still.toml", SCENE);
    let still = |set: &[&str]| {
        let mut args = vec![
            "render",
            "still.toml",
            "-q",
            "--spp",
            "3",
            "-o",
            "still.png",
        ];
        for s in set {
            args.extend(["--set", s]);
        }
        timbre(server.path(), &args).assert_success();
        decode_png(&server.path().join("still.png"))
    };
    let mut page = server.connect().await;
    let state = page.json("scene").await;
    assert_eq!(
        state["animation"],
        serde_json::json!({"frames": 5, "frame": null})
    );
    let written = page.converged(0).await;
    assert_eq!(written.differences(&still(&[])), 0, "the scene as written");

    page.send(serde_json::json!({"type": "frame", "frame": 3}))
        .await;
    let state = page.json("scene").await;
    assert_eq!(state["animation"]["frame"], 3);
    let position = state["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["key"] == "camera.position")
        .map(|p| p["value"].clone());
    // Linear interpolation, u = 3/4 of the way, in f64 as any code does it.
    let (x, y) = (0.0 + 0.75 * (0.4 - 0.0), 0.0 + 0.75 * (0.2 - 0.0));
    let position: Vec<f64> = position
        .unwrap()
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(position, [x, y, 0.0]);
    let third = page.converged(written.generation).await;
    let expected = still(&[&format!("camera.position=[{x:?}, {y:?}, 0]")]);
    assert_eq!(third.differences(&expected), 0, "frame 3");
    assert!(written.differences(&expected) > 100, "the camera moved");
    // As `timbre render --frame 3` does, a --set of the animated value is refused.
    page.send(serde_json::json!({"type": "set", "set": ["camera.position=[1, 0, 0]"]}))
        .await;
    page.error("is animated by the scene's [animation], whose frame 3 is shown")
        .await;
    page.send(serde_json::json!({"type": "unset", "keys": []}))
        .await;
    assert_eq!(page.json("scene").await["animation"]["frame"], 3);
    let third = page.converged(third.generation).await;
    assert_eq!(third.differences(&expected), 0, "frame 3 again");

    page.send(serde_json::json!({"type": "frame", "frame": 9}))
        .await;
    assert_eq!(page.json("scene").await["animation"]["frame"], 4);
    let last = page.converged(third.generation).await;
    assert_eq!(
        last.differences(&still(&["camera.position=[0.4, 0.2, 0]"])),
        0
    );

    page.send(serde_json::json!({"type": "frame", "frame": null}))
        .await;
    assert!(page.json("scene").await["animation"]["frame"].is_null());
    let back = page.converged(last.generation).await;
    assert_eq!(back.differences(&still(&[])), 0);
}
