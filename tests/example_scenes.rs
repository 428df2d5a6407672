//! What the example scenes show. Every scene in `scenes/` is rendered (small, one sample per
//! pixel unless the fact is about sampling) or its lines of sight are traced (`timbre trace`,
//! with rays added to a copy of the file), and the test checks a fact about the picture that is
//! worked out here, independently of timbre: from the Dr TIM paper's equations, textbook
//! optics and the numbers in the scene file itself (where the lattice must appear for the
//! camera's field of view, which way a lens turns the picture, which object a line of sight
//! ends on). A wrong number in a scene file breaks its test.
//!
//! The object-id, depth and normal AOVs say which object each pixel centre sees, where and
//! facing which way; `timbre trace --json` gives the points where a ray meets each surface,
//! the object it ends on and its last direction. Colours are read from OpenEXR (linear, f32).

mod common;

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};

use exr::prelude::{AttributeValue, FlatSamples};
use glam::{DMat3, DVec3};
use tempfile::TempDir;

use common::cli::{path_str, timbre, write};

// ------------------------------------------------------------------------------------------
// Running timbre
// ------------------------------------------------------------------------------------------

/// The example scene `scenes/NAME.toml`.
fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.toml"))
}

/// A copy of the example scene `name` with `extra` (TOML tables, e.g. `[[ray_trajectory]]`s)
/// appended, in a temporary directory that also links the scenes' meshes.
fn scene_with(name: &str, extra: &str) -> (TempDir, PathBuf) {
    let dir = TempDir::new().unwrap();
    let text = std::fs::read_to_string(scene(name)).unwrap();
    let path = write(&dir, "scene.toml", format!("{text}\n{extra}\n"));
    std::os::unix::fs::symlink(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes"),
        dir.path().join("meshes"),
    )
    .unwrap();
    (dir, path)
}

/// A render read back from its OpenEXR file: the colour channels and AOVs (in the file's data
/// window, which is the whole image unless `--pixel-bounds` was given) and the object names.
struct Picture {
    /// The whole image's size.
    size: (usize, usize),
    /// The data window: its top-left pixel and size.
    origin: (usize, usize),
    window: (usize, usize),
    channels: HashMap<String, Vec<f32>>,
    names: Vec<String>,
}

impl Picture {
    fn read(path: &Path) -> Picture {
        let image = exr::prelude::read_all_flat_layers_from_file(path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let layer = &image.layer_data[0];
        let channels = layer
            .channel_data
            .list
            .iter()
            .filter_map(|c| match &c.sample_data {
                FlatSamples::F32(values) => Some((c.name.to_string(), values.clone())),
                _ => None,
            })
            .collect();
        let names = layer
            .attributes
            .other
            .iter()
            .find(|(key, _)| *key == "timbre.objects")
            .map(|(_, value)| match value {
                AttributeValue::TextVector(names) => names.iter().map(|n| n.to_string()).collect(),
                other => panic!("timbre.objects: {other:?}"),
            })
            .unwrap_or_default();
        let p = layer.attributes.layer_position;
        let full = image.attributes.display_window.size;
        Picture {
            size: (full.0, full.1),
            origin: (p.0 as usize, p.1 as usize),
            window: (layer.size.0, layer.size.1),
            channels,
            names,
        }
    }

    /// The value of `channel` at pixel (x, y) of the whole image.
    #[track_caller]
    fn value(&self, channel: &str, x: usize, y: usize) -> f32 {
        let (ox, oy) = self.origin;
        assert!(
            x >= ox && y >= oy && x < ox + self.window.0 && y < oy + self.window.1,
            "pixel ({x}, {y}) is outside the rendered window"
        );
        self.channels[channel][(y - oy) * self.window.0 + (x - ox)]
    }

    fn rgb(&self, x: usize, y: usize) -> DVec3 {
        DVec3::new(
            self.value("R", x, y) as f64,
            self.value("G", x, y) as f64,
            self.value("B", x, y) as f64,
        )
    }

    /// The name of the object the pixel centre sees ("nothing" where it sees none).
    fn object(&self, x: usize, y: usize) -> &str {
        let id = self.value("object.id", x, y);
        if id < 0.0 {
            "nothing"
        } else {
            &self.names[id as usize]
        }
    }

    fn depth(&self, x: usize, y: usize) -> f64 {
        self.value("depth.Z", x, y) as f64
    }

    fn normal(&self, x: usize, y: usize) -> DVec3 {
        DVec3::new(
            self.value("normal.X", x, y) as f64,
            self.value("normal.Y", x, y) as f64,
            self.value("normal.Z", x, y) as f64,
        )
    }

    /// Every pixel of the data window.
    fn pixels(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let (ox, oy) = self.origin;
        let (w, h) = self.window;
        (oy..oy + h).flat_map(move |y| (ox..ox + w).map(move |x| (x, y)))
    }
}

/// Renders the scene file `path` to OpenEXR with the options `args` and reads it back.
#[track_caller]
fn render_file(path: &Path, args: &[&str]) -> Picture {
    let dir = TempDir::new().unwrap();
    let mut all = vec!["render", "-q", path_str(path), "-o", "out.exr"];
    all.extend_from_slice(args);
    timbre(dir.path(), &all).assert_success();
    Picture::read(&dir.path().join("out.exr"))
}

/// Renders the example scene `name` at `width` × `height`, one sample per pixel through each
/// pixel centre, with the depth, normal and object AOVs.
#[track_caller]
fn render(name: &str, width: usize, height: usize) -> Picture {
    let (w, h) = (width.to_string(), height.to_string());
    let args = ["--width", &w, "--height", &h, "--spp", "1"];
    render_file(
        &scene(name),
        &[&args[..], &["--aov", "depth,normal,object"]].concat(),
    )
}

/// Renders scene text (written to a temporary file) like [`render`].
#[track_caller]
fn render_text(text: &str, width: usize, height: usize) -> Picture {
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "scene.toml", text);
    let (w, h) = (width.to_string(), height.to_string());
    render_file(
        &path,
        &[
            "--width",
            &w,
            "--height",
            &h,
            "--spp",
            "1",
            "--aov",
            "depth,normal,object",
        ],
    )
}

/// One ray of `timbre trace --json`.
#[derive(Debug)]
struct Traced {
    trajectory: String,
    end: String,
    direction: DVec3,
    points: Vec<Point>,
}

#[derive(Debug)]
struct Point {
    position: DVec3,
    arrival: String,
    object: Option<String>,
}

impl Traced {
    /// The object the ray ends on (the last point's).
    fn last_object(&self) -> &str {
        self.points
            .last()
            .and_then(|p| p.object.as_deref())
            .unwrap_or("nothing")
    }

    fn last(&self) -> DVec3 {
        self.points.last().unwrap().position
    }

    /// The points on the object `name` (where the ray meets it, enters or leaves it).
    fn on(&self, name: &str) -> Vec<DVec3> {
        self.points
            .iter()
            .filter(|p| p.object.as_deref() == Some(name))
            .map(|p| p.position)
            .collect()
    }
}

fn vector(value: &serde_json::Value) -> DVec3 {
    let v: Vec<f64> = value
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    DVec3::from_slice(&v)
}

/// The rays of the scene file `path`, traced by `timbre trace --json`.
#[track_caller]
fn trace_file(path: &Path) -> Vec<Traced> {
    trace_file_with(path, &[])
}

/// [`trace_file`] with more options (`--set KEY=VALUE`).
#[track_caller]
fn trace_file_with(path: &Path, options: &[&str]) -> Vec<Traced> {
    let dir = TempDir::new().unwrap();
    let args = [&["trace", "--json", path_str(path)], options].concat();
    let run = timbre(dir.path(), &args);
    run.assert_success();
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    json["rays"]
        .as_array()
        .unwrap()
        .iter()
        .map(|ray| Traced {
            trajectory: ray["trajectory"].as_str().unwrap().to_string(),
            end: ray["end"].as_str().unwrap().to_string(),
            direction: vector(&ray["direction"]),
            points: ray["points"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| Point {
                    position: vector(&p["position"]),
                    arrival: p["arrival"].as_str().unwrap().to_string(),
                    object: p["object"].as_str().map(str::to_string),
                })
                .collect(),
        })
        .collect()
}

/// The example scene `name` with the rays `rays` (from [`ray`]) added, traced; only the added
/// rays are returned, in order.
#[track_caller]
fn trace(name: &str, rays: &[String]) -> Vec<Traced> {
    trace_with(name, rays, &[])
}

/// [`trace`] with more options (`--set KEY=VALUE`).
#[track_caller]
fn trace_with(name: &str, rays: &[String], options: &[&str]) -> Vec<Traced> {
    let (_dir, path) = scene_with(name, &rays.concat());
    trace_file_with(&path, options)
        .into_iter()
        .filter(|r| r.trajectory.starts_with("test ray "))
        .collect()
}

/// A `[[ray_trajectory]]` table for one ray, the `k`th of a test.
fn ray(k: usize, start: DVec3, direction: DVec3) -> String {
    format!(
        "\n[[ray_trajectory]]\nname = \"test ray {k}\"\nstart = {}\ndirection = {}\nmax_interactions = 100\n",
        toml_vector(start),
        toml_vector(direction)
    )
}

fn toml_vector(v: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

// ------------------------------------------------------------------------------------------
// Geometry worked out here
// ------------------------------------------------------------------------------------------

/// TIM's pinhole camera (docs/SCENE_FORMAT.md, "Projection"): the detector at distance 1, the
/// horizontal view angle spanning the centres of the outermost pixel columns, square pixels,
/// right = up × view direction.
#[derive(Clone, Copy, Debug)]
struct Camera {
    position: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    pitch: f64,
    width: usize,
    height: usize,
}

impl Camera {
    fn new(
        position: DVec3,
        view: DVec3,
        up: DVec3,
        angle_deg: f64,
        width: usize,
        height: usize,
    ) -> Camera {
        let forward = view.normalize();
        let right = up.cross(forward).normalize();
        Camera {
            position,
            forward,
            right,
            up: forward.cross(right),
            pitch: 2.0 * (angle_deg.to_radians() / 2.0).tan() / (width - 1) as f64,
            width,
            height,
        }
    }

    /// TIM's standard camera (at the origin, looking along +z, up +y) with a view angle.
    fn standard(angle_deg: f64, width: usize, height: usize) -> Camera {
        Camera::new(DVec3::ZERO, DVec3::Z, DVec3::Y, angle_deg, width, height)
    }

    /// The direction (not normalised) through the point (x, y) of the image, in pixels from
    /// the top-left pixel's centre.
    fn direction(&self, x: f64, y: f64) -> DVec3 {
        let cx = 0.5 * (self.width - 1) as f64;
        let cy = 0.5 * (self.height - 1) as f64;
        self.forward + (x - cx) * self.pitch * self.right + (cy - y) * self.pitch * self.up
    }

    /// Where the point `p` appears in the image, in pixels.
    fn pixel(&self, p: DVec3) -> (f64, f64) {
        self.pixel_of_direction(p - self.position)
    }

    /// Where light arriving against the direction `d` appears, in pixels.
    fn pixel_of_direction(&self, d: DVec3) -> (f64, f64) {
        let f = d.dot(self.forward);
        assert!(f > 0.0, "{d} is behind the camera");
        let cx = 0.5 * (self.width - 1) as f64;
        let cy = 0.5 * (self.height - 1) as f64;
        (
            cx + d.dot(self.right) / f / self.pitch,
            cy - d.dot(self.up) / f / self.pitch,
        )
    }

    /// The pixel nearest to where `p` appears.
    fn pixel_of(&self, p: DVec3) -> (usize, usize) {
        let (x, y) = self.pixel(p);
        (x.round() as usize, y.round() as usize)
    }
}

/// Eq 4 of the paper: the direction, in the scene frame, of a ray traced backwards with
/// direction `d` from a camera moving with velocity `beta` (in units of c).
fn aberrate(d: DVec3, beta: DVec3) -> DVec3 {
    let b2 = beta.length_squared();
    if b2 == 0.0 {
        return d;
    }
    let gamma = 1.0 / (1.0 - b2).sqrt();
    d + (gamma - 1.0) * beta.dot(d) * beta / b2 - gamma * beta * d.length()
}

/// The inverse of [`aberrate`]: the camera-frame direction of a backwards ray whose
/// scene-frame direction is `d` (the Lorentz transformation with −β).
fn unaberrate(d: DVec3, beta: DVec3) -> DVec3 {
    aberrate(d, -beta)
}

/// Distance from `p` to the segment from `a` to `b`.
fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (p - (a + t * ab)).length()
}

/// Distance from `p` to the line through `a` along `d`.
fn line_distance(p: DVec3, a: DVec3, d: DVec3) -> f64 {
    let d = d.normalize();
    let ap = p - a;
    (ap - ap.dot(d) * d).length()
}

/// The cylinder lattices of TIM's studios (docs/SCENE_FORMAT.md, "studio"), 48 cylinders of
/// radius 0.02: red along z, blue along x, green along y.
#[derive(Clone, Copy, Debug)]
enum Lattice {
    /// `studio = "lattice"`: x ∈ {±1, ±1/3}, y ∈ {−0.98, −0.98 + 2/3, −0.98 + 4/3, 1.02},
    /// z ∈ {10, 20, 30, 40}.
    Standard,
    /// `studio = "metatoy-window"`: x, y ∈ {±0.98, ±0.98/3}, z ∈ {11, 20, 29, 38}.
    Metatoy,
}

impl Lattice {
    /// The cylinders' colours and axes (from end to end).
    fn cylinders(self) -> Vec<(&'static str, DVec3, DVec3)> {
        let (xs, ys, zs) = match self {
            Lattice::Standard => (
                [-1.0, -1.0 / 3.0, 1.0 / 3.0, 1.0],
                [-0.98, -0.98 + 2.0 / 3.0, -0.98 + 4.0 / 3.0, 1.02],
                [10.0, 20.0, 30.0, 40.0],
            ),
            Lattice::Metatoy => {
                let a = [-0.98, -0.98 / 3.0, 0.98 / 3.0, 0.98];
                (a, a, [11.0, 20.0, 29.0, 38.0])
            }
        };
        let mut cylinders = Vec::new();
        for a in 0..4 {
            for b in 0..4 {
                cylinders.push((
                    "red",
                    DVec3::new(xs[a], ys[b], zs[0]),
                    DVec3::new(xs[a], ys[b], zs[3]),
                ));
                cylinders.push((
                    "blue",
                    DVec3::new(xs[0], ys[a], zs[b]),
                    DVec3::new(xs[3], ys[a], zs[b]),
                ));
                cylinders.push((
                    "green",
                    DVec3::new(xs[a], ys[0], zs[b]),
                    DVec3::new(xs[a], ys[3], zs[b]),
                ));
            }
        }
        cylinders
    }

    /// The distance from `p` to the nearest axis of the cylinders of `colour`.
    fn distance(self, colour: &str, p: DVec3) -> f64 {
        self.cylinders()
            .iter()
            .filter(|c| c.0 == colour)
            .map(|&(_, a, b)| segment_distance(p, a, b))
            .fold(f64::INFINITY, f64::min)
    }

    /// What a ray from `origin` along `d` sees in the studio with this lattice and nothing
    /// else: "red", "green" or "blue" (a cylinder), "floor" or "sky"; `None` where it grazes
    /// a cylinder (where cylinders 1e-4 thinner or thicker would make a difference).
    fn sees(self, origin: DVec3, d: DVec3) -> Option<&'static str> {
        let d = d.normalize();
        // The sky sphere (about the origin) from inside, and the floor if it is nearer.
        let b = origin.dot(d);
        let sky = -b + (b * b - origin.length_squared() + SKY_RADIUS * SKY_RADIUS).sqrt();
        let floor = if d.y < 0.0 {
            (FLOOR_Y - origin.y) / d.y
        } else {
            f64::INFINITY
        };
        if (floor / sky - 1.0).abs() < 0.01 {
            return None;
        }
        let first = |radius: f64| {
            let mut hits = vec![if floor < sky {
                (floor, "floor")
            } else {
                (sky, "sky")
            }];
            for (colour, a, b) in self.cylinders() {
                if let Some(t) = capped_cylinder_hit(origin, d, a, b, radius) {
                    hits.push((t, colour));
                }
            }
            hits.sort_by(|a, b| a.0.total_cmp(&b.0));
            // Where two cylinders of different colours cross, either may be seen first.
            match hits.get(1) {
                Some(next) if next.1 != hits[0].1 && next.0 - hits[0].0 < 1e-3 => "unclear",
                _ => hits[0].1,
            }
        };
        let seen = first(0.02);
        (seen != "unclear" && first(0.0199) == seen && first(0.0201) == seen).then_some(seen)
    }
}

/// Where the ray from `origin` along the unit direction `d` first meets the capped cylinder of
/// radius `r` round the segment from `a` to `b`, from outside.
fn capped_cylinder_hit(origin: DVec3, d: DVec3, a: DVec3, b: DVec3, r: f64) -> Option<f64> {
    let ba = b - a;
    let oc = origin - a;
    let baba = ba.dot(ba);
    let bard = ba.dot(d);
    let baoc = ba.dot(oc);
    let k2 = baba - bard * bard;
    let k1 = baba * oc.dot(d) - baoc * bard;
    let k0 = baba * oc.dot(oc) - baoc * baoc - r * r * baba;
    let h = k1 * k1 - k2 * k0;
    if h < 0.0 {
        return None;
    }
    let h = h.sqrt();
    let t = (-k1 - h) / k2;
    let y = baoc + t * bard;
    if y > 0.0 && y < baba {
        return (t > 0.0).then_some(t);
    }
    // The cap on the side the ray comes from.
    let t = (if y < 0.0 { 0.0 } else { baba } - baoc) / bard;
    ((k1 + k2 * t).abs() < h && t > 0.0).then_some(t)
}

/// Whether the colour `c` is what a ray that sees `seen` (from [`Lattice::sees`]) shows,
/// dimmed by `transmission`: the sky's colour, the grey of the lit floor (white light on grey
/// tiles), or a cylinder's, whose diffuse colour is pure red, green or blue and whose specular
/// highlights are white. A negative `transmission` stands for any power (up to the 12th) of
/// its magnitude: light through an unknown number of lenses.
fn shows(c: DVec3, seen: &str, transmission: f64) -> bool {
    if transmission < 0.0 {
        return (0..=12).any(|k| shows(c, seen, (-transmission).powi(k)));
    }
    let equal = |a: f64, b: f64| (a - b).abs() <= 1e-6 * (1.0 + a.abs());
    match seen {
        "sky" => (c - transmission * SKY).length() < 1e-6,
        "floor" => equal(c.x, c.y) && equal(c.y, c.z) && c.x > 0.0,
        "red" => equal(c.y, c.z) && c.x > c.y + 0.05 * transmission,
        "green" => equal(c.x, c.z) && c.y > c.x + 0.05 * transmission,
        "blue" => {
            equal(c.x, c.y)
                && c.z > c.x + 0.05 * transmission
                && (c - transmission * SKY).length() > 1e-3
        }
        _ => unreachable!("{seen}"),
    }
}

/// Asserts [`shows`].
#[track_caller]
fn assert_shows(what: &str, c: DVec3, seen: &str, transmission: f64) {
    assert!(
        shows(c, seen, transmission),
        "{what} shows {c}, not the {seen}"
    );
}

/// The colour of the lattice cylinder named `name` ("red cylinder 1,2"), or `None`.
fn cylinder_colour(name: &str) -> Option<&str> {
    let (colour, _) = name.split_once(" cylinder ")?;
    ["red", "green", "blue"].contains(&colour).then_some(colour)
}

/// The floor plane of TIM's studio.
const FLOOR_Y: f64 = -1.0001;
/// TIM's sky colour.
const SKY: DVec3 = DVec3::new(0.5, 0.5, 1.0);
/// The fraction of the light Dr TIM's surfaces pass on where a scene does not say
/// (`SurfacePropertyPrimitive.DEFAULT_TRANSMISSION_COEFFICIENT`): §3's lenses, crossed as one
/// surface, dim what is seen through them by it once.
const DEFAULT_TRANSMISSION_COEFFICIENT: f64 = 0.96;
/// The radius of TIM's sky sphere.
const SKY_RADIUS: f64 = 1e5;

/// Checks every pixel of a render of a lattice studio, seen through nothing, against the
/// geometry: a pixel whose (scene-frame) line of sight from `eye` along `direction(x, y)`
/// sees the floor must see it where that line meets the plane y = −1.0001 (the depth AOV
/// gives the distance), one that sees a cylinder must see a point 0.02 from one of that
/// colour's axes, and one that sees the sky must look up (or so nearly level that the floor is
/// beyond the sky). Returns how many pixels see the floor, the lattice and the sky.
#[track_caller]
fn assert_studio_geometry(
    picture: &Picture,
    eye: DVec3,
    direction: impl Fn(usize, usize) -> DVec3,
) -> (usize, usize, usize) {
    let (mut floor, mut lattice, mut sky) = (0, 0, 0);
    for (x, y) in picture.pixels() {
        let d = direction(x, y).normalize();
        let p = eye + picture.depth(x, y) * d;
        let name = picture.object(x, y);
        match name {
            "floor" => {
                assert!(
                    d.y < 0.0 && (p.y - FLOOR_Y).abs() < 1e-4,
                    "pixel ({x}, {y}) sees the floor at {p}, off the line of sight {d}"
                );
                floor += 1;
            }
            "sky" => {
                assert!(
                    d.y > -2.0 * (FLOOR_Y - eye.y).abs() / SKY_RADIUS,
                    "pixel ({x}, {y}) sees the sky along {d}, which meets the floor first"
                );
                sky += 1;
            }
            _ => {
                let colour =
                    cylinder_colour(name).unwrap_or_else(|| panic!("pixel ({x}, {y}) sees {name}"));
                let distance = Lattice::Standard.distance(colour, p);
                assert!(
                    distance < 0.0201,
                    "pixel ({x}, {y}) sees the {name} at {p}, {distance} from every {colour} \
                     cylinder's axis"
                );
                lattice += 1;
            }
        }
    }
    (floor, lattice, sky)
}

/// The angle between two directions.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.normalize().dot(b.normalize()).clamp(-1.0, 1.0).acos()
}

/// The lattice's eight outermost points (its bounding box, widened by the cylinders' radius).
fn lattice_corners() -> Vec<DVec3> {
    let mut corners = Vec::new();
    for x in [-1.02, 1.02] {
        for y in [-1.0, 1.04] {
            for z in [9.98, 40.02] {
                corners.push(DVec3::new(x, y, z));
            }
        }
    }
    corners
}

// ------------------------------------------------------------------------------------------
// §2: relativistic cameras
// ------------------------------------------------------------------------------------------

/// scenes/fig2a-at-rest.toml (Fig. 2(a)): a pinhole camera at rest with a 30° view. Every pixel
/// sees the floor, a cylinder or the sky where its straight line of sight through TIM's pixel
/// grid meets them, and the green cylinders of the lattice's front row (z = 10) stand at the
/// columns of their positions x ∈ {±1, ±1/3}: 30 and 10 pixels from the centre at 160 pixels'
/// width (45 and 15 with the studio's 20°).
#[test]
fn fig2a_shows_the_lattice_through_a_30_degree_pinhole_at_rest() {
    let camera = Camera::standard(30.0, 320, 240);
    let picture = render("fig2a-at-rest", 320, 240);
    let (floor, lattice, sky) = assert_studio_geometry(&picture, DVec3::ZERO, |x, y| {
        camera.direction(x as f64, y as f64)
    });
    assert!(
        floor > 20_000 && sky > 20_000 && lattice > 1000,
        "{floor} floor, {lattice} lattice and {sky} sky pixels"
    );
    for x in [-1.0, -1.0 / 3.0, 1.0 / 3.0, 1.0] {
        // Halfway up the cylinder, where nothing else is in the way.
        let (px, py) = camera.pixel_of(DVec3::new(x, 0.5, 10.0));
        let p = picture.depth(px, py) * camera.direction(px as f64, py as f64).normalize();
        assert!(
            picture.object(px, py).starts_with("green cylinder") && (p.z - 10.0).abs() < 0.021,
            "pixel ({px}, {py}) sees the {} at {p}, not the green cylinder at x = {x}, z = 10",
            picture.object(px, py)
        );
    }
}

/// scenes/fig2b-forwards-0.99c.toml (Fig. 2(b)): the pinhole camera moving at v = (0, 0, 0.99c).
/// Every pixel's line of sight is the camera's pixel direction turned by relativistic
/// aberration (Eq 4) into the scene frame, and sees the floor, cylinder or sky there. The
/// lattice, 5° to 8° off the axis at rest, is squeezed into the directions aberration maps the
/// lattice's corners to (under 0.6° of the centre), and the picture's corners look more than
/// 90° away from the direction of motion: the camera sees the floor behind the point it was
/// at when the shutter opened.
#[test]
fn fig2b_forwards_at_0_99c_squeezes_the_lattice_into_the_centre() {
    let (width, height) = (320, 240);
    let camera = Camera::standard(30.0, width, height);
    let beta = DVec3::new(0.0, 0.0, 0.99);
    let picture = render("fig2b-forwards-0.99c", width, height);
    let (floor, lattice, sky) = assert_studio_geometry(&picture, DVec3::ZERO, |x, y| {
        aberrate(camera.direction(x as f64, y as f64), beta)
    });
    assert!(
        floor > 20_000 && sky > 20_000 && lattice > 10,
        "{floor} floor, {lattice} lattice and {sky} sky pixels"
    );
    let widest = lattice_corners()
        .into_iter()
        .map(|p| angle(unaberrate(p, beta), DVec3::Z))
        .fold(0.0, f64::max);
    let mut farthest: f64 = 0.0;
    for (x, y) in picture.pixels() {
        if cylinder_colour(picture.object(x, y)).is_some() {
            farthest = farthest.max(angle(camera.direction(x as f64, y as f64), DVec3::Z));
        }
    }
    assert!(
        widest < 0.6f64.to_radians() && farthest <= widest + camera.pitch,
        "the lattice is seen up to {farthest} rad off the axis, beyond {widest}"
    );
    let behind = picture
        .pixels()
        .filter(|&(x, y)| {
            picture.object(x, y) == "floor"
                && (picture.depth(x, y)
                    * aberrate(camera.direction(x as f64, y as f64), beta).normalize())
                .z < 0.0
        })
        .count();
    assert!(
        behind > 1000,
        "{behind} pixels see the floor behind the camera"
    );
}

/// scenes/fig2c-oblique-0.99c.toml (Fig. 2(c)): the camera moving at v = (0.2c, 0, 0.97c), still
/// looking along +z. Every line of sight is Eq 4's, and the lattice is seen only within the
/// directions its corners are aberrated to, crowded round the direction of motion, 11.7° to
/// the right of the centre; the direction it is seen in at the camera's speed, its middle's,
/// is about 11° right.
#[test]
fn fig2c_oblique_at_0_99c_crowds_the_lattice_to_the_right() {
    let (width, height) = (320, 240);
    let camera = Camera::standard(30.0, width, height);
    let beta = DVec3::new(0.2, 0.0, 0.97);
    let picture = render("fig2c-oblique-0.99c", width, height);
    let (floor, lattice, sky) = assert_studio_geometry(&picture, DVec3::ZERO, |x, y| {
        aberrate(camera.direction(x as f64, y as f64), beta)
    });
    assert!(
        floor > 20_000 && sky > 20_000 && lattice > 10,
        "{floor} floor, {lattice} lattice and {sky} sky pixels"
    );
    let middle = unaberrate(DVec3::new(0.0, 0.02, 25.0), beta);
    let widest = lattice_corners()
        .into_iter()
        .map(|p| angle(unaberrate(p, beta), middle))
        .fold(0.0, f64::max);
    let (mut sum, mut farthest) = (0.0, 0.0f64);
    for (x, y) in picture.pixels() {
        if cylinder_colour(picture.object(x, y)).is_some() {
            let d = camera.direction(x as f64, y as f64);
            farthest = farthest.max(angle(d, middle));
            sum += x as f64;
        }
    }
    assert!(
        farthest <= widest + camera.pitch,
        "the lattice is seen up to {farthest} rad from its middle's direction, beyond {widest}"
    );
    let right = middle.x.atan2(middle.z).to_degrees();
    assert!((10.0..12.0).contains(&right), "{right}°");
    let (mx, _) = camera.pixel_of_direction(middle);
    let mean = sum / lattice as f64;
    assert!(
        (mean - mx).abs() < 2.0,
        "the lattice's pixels are centred on column {mean}, not {mx}"
    );
}

/// The fraction of a uniform disc of radius `a` centred on 0 whose y coordinate is below `c`.
fn disc_fraction_below(c: f64, a: f64) -> f64 {
    let c = c.clamp(-a, a);
    0.5 + (c * (a * a - c * c).sqrt() + a * a * (c / a).asin()) / (PI * a * a)
}

/// scenes/fig3-finite-aperture-0.99c.toml (Fig. 3): the camera of Fig. 2(b) (v = 0.99c along
/// the view direction; its default 20° view) with an entrance pupil of radius 0.02, focused
/// 15 tiles ahead in the camera frame.
///
/// The chief ray of each pixel (through the pupil's centre, as the AOVs see it) is Eq 4's line
/// of sight. And the horizon is blurred exactly as the aperture and focus distance say: a ray
/// from the pupil point E towards the pixel's image I = 15 (u, v, 1) goes up, and so sees the
/// sky rather than the floor, if and only if E_y < 15 v (aberration along z does not change a
/// direction's y component, and the pupil is level with the sky's horizon). So the fraction
/// of a pixel's 64 samples that see the sky, 2 (B − R) since the sky is (0.5, 0.5, 1) and the
/// floor grey, is the fraction of the pupil disc below 15 v, averaged over the pixel: a
/// transition ±2.4 rows wide at 640 × 480 where a pinhole has a sharp edge.
#[test]
fn fig3_finite_aperture_blurs_the_horizon_by_aperture_over_focus_distance() {
    let (a, focus) = (0.02, 15.0);
    let beta = DVec3::new(0.0, 0.0, 0.99);

    // With one sample per pixel, each pixel shows what one ray from a point E of the pupil sees.
    // A lattice point P is seen by the ray from E (where it starts, at t = 0, also in the scene
    // frame) along Eq 4's inverse of P − E, in the pixel whose image point on the focus plane
    // that ray passes: the lattice's pixels lie within the directions of its corners seen
    // from the pupil's rim.
    let camera = Camera::standard(20.0, 160, 120);
    let picture = render("fig3-finite-aperture-0.99c", 160, 120);
    let mut widest: f64 = 0.0;
    for corner in lattice_corners() {
        for k in 0..32 {
            let phi = k as f64 * PI / 16.0;
            let e = a * DVec3::new(phi.cos(), phi.sin(), 0.0);
            let d = unaberrate(corner - e, beta);
            let image = e + (focus / d.z) * d;
            widest = widest.max(angle(image, DVec3::Z));
        }
    }
    let mut lattice = 0;
    for (x, y) in picture.pixels() {
        let c = picture.rgb(x, y);
        let grey = c.x == c.y && c.y == c.z;
        if !grey && c != SKY {
            lattice += 1;
            let off = angle(camera.direction(x as f64, y as f64), DVec3::Z);
            assert!(
                off <= widest + camera.pitch,
                "pixel ({x}, {y}) shows a cylinder {off} rad off the axis, beyond {widest}"
            );
        }
    }
    assert!(
        widest < 0.7f64.to_radians() && lattice > 0,
        "{lattice} lattice pixels within {widest}"
    );

    // 64 columns 5° to 7° left of the centre, far from the lattice, with the scene's 64 samples.
    let (width, height) = (640, 480);
    let camera = Camera::standard(20.0, width, height);
    let picture = render_file(
        &scene("fig3-finite-aperture-0.99c"),
        &[
            "--width",
            "640",
            "--height",
            "480",
            "--pixel-bounds",
            "100,164,230,250",
        ],
    );
    for y in 230..250 {
        let measured = (100..164)
            .map(|x| {
                let c = picture.rgb(x, y);
                2.0 * (c.z - c.x)
            })
            .sum::<f64>()
            / 64.0;
        let steps = 1000;
        let expected = (0..steps)
            .map(|k| {
                let py = y as f64 - 0.5 + (k as f64 + 0.5) / steps as f64;
                let v = camera.direction(0.0, py).y;
                disc_fraction_below(focus * v, a)
            })
            .sum::<f64>()
            / steps as f64;
        assert!(
            (measured - expected).abs() < 0.03,
            "row {y}: {measured} of the samples see the sky, not {expected}"
        );
    }
}

/// Luminance of a linear RGB colour, as the anaglyphs weigh it (Rec. 709).
fn luminance(c: DVec3) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The smallest box of pixels that contains where the points `points` appear to an eye at
/// `eye` (in the scene frame, at t = 0) of a camera at the origin moving with `beta`, whose
/// rays go from the eye towards each pixel's image on the plane `focus` ahead (the stereo
/// cameras' convergence), widened by `margin` pixels: (x0, x1, y0, y1).
fn stereo_box(
    camera: &Camera,
    eye: DVec3,
    beta: DVec3,
    focus: f64,
    points: &[DVec3],
    margin: f64,
) -> (f64, f64, f64, f64) {
    let mut b = (f64::INFINITY, -f64::INFINITY, f64::INFINITY, -f64::INFINITY);
    for &p in points {
        let d = unaberrate(p - eye, beta);
        let image = eye + (focus / d.z) * d;
        let (x, y) = camera.pixel_of_direction(image);
        b = (b.0.min(x), b.1.max(x), b.2.min(y), b.3.max(y));
    }
    (b.0 - margin, b.1 + margin, b.2 - margin, b.3 + margin)
}

/// The lattice and the floor its shadows fall on (the light is at (100, 300, −500), so a
/// shadow lies up to 3.4 tiles behind and 0.7 to the left of what throws it): the box in which
/// everything dark in a picture of the lattice studio lies.
fn lattice_and_shadows() -> Vec<DVec3> {
    let mut corners = Vec::new();
    for x in [-1.7, 1.02] {
        for y in [FLOOR_Y, 1.04] {
            for z in [9.98, 43.5] {
                corners.push(DVec3::new(x, y, z));
            }
        }
    }
    corners
}

/// scenes/fig4-relativistic-anaglyph.toml (Fig. 4): a red-blue anaglyph of two eyes 0.4 apart
/// along x, both moving at v = (0, 0, 0.99c), converging on the plane 10 ahead. The picture
/// has no green; where both eyes see the sky, red and blue are both the sky's luminance
/// 0.5361. Each eye sees the lattice squeezed by aberration into a small patch whose place
/// follows from its position: the left eye's pixel for a point P is where its ray along Eq 4's
/// inverse of P − E_L meets the convergence plane. Moving at 0.99c the patches lie about 17
/// pixels left (red) and right (blue) of the centre at 320 pixels' width, apart (at rest
/// the front of the lattice, on the convergence plane, would be seen by both eyes in the
/// same place): every dark pixel (the lattice's red and blue cylinders and their shadows)
/// of the red channel lies in the left eye's patch and of the blue channel in the right eye's.
#[test]
fn fig4_relativistic_anaglyph_shows_each_eyes_squeezed_lattice_apart() {
    let (width, height) = (320, 240);
    let picture = render_file(
        &scene("fig4-relativistic-anaglyph"),
        &["--width", "320", "--height", "240", "--spp", "1"],
    );
    let camera = Camera::standard(20.0, width, height);
    let beta = DVec3::new(0.0, 0.0, 0.99);
    let sky = luminance(SKY);
    for (x, y) in picture.pixels() {
        assert_eq!(picture.value("G", x, y), 0.0, "green at ({x}, {y})");
    }
    for x in 0..width {
        let c = picture.rgb(x, 0);
        assert!(
            (c.x - sky).abs() < 1e-6 && (c.z - sky).abs() < 1e-6,
            "{c} at ({x}, 0)"
        );
    }
    let dark = lattice_and_shadows();
    let view = |eye: f64| stereo_box(&camera, DVec3::new(eye, 0.0, 0.0), beta, 10.0, &dark, 1.0);
    assert!(
        view(-0.2).1 < view(0.2).0,
        "the eyes' views of the lattice overlap"
    );
    for (eye, channel, colour) in [(-0.2, "R", "red"), (0.2, "B", "blue")] {
        let (x0, x1, y0, y1) = view(eye);
        let mut count = 0;
        for (x, y) in picture.pixels() {
            if picture.value(channel, x, y) < 0.45 {
                count += 1;
                let (fx, fy) = (x as f64, y as f64);
                assert!(
                    fx >= x0 && fx <= x1 && fy >= y0 && fy <= y1,
                    "the {colour} channel is dark at ({x}, {y}), outside the eye's view of \
                     the lattice, columns {x0} to {x1} and rows {y0} to {y1}"
                );
            }
        }
        assert!(count > 10, "{count} dark pixels in the {colour} channel");
    }
}

/// Whether a colour is that of a lit green cylinder of the lattice (diffuse green, specular
/// white), not the sky, the floor or another cylinder.
fn is_green(c: DVec3) -> bool {
    c.y > c.x + 0.1 && c.y > c.z + 0.1
}

/// scenes/3d-tv-side-by-side.toml: a "side-by-side (half)" 3D-TV frame of the lattice, eyes
/// 0.2 apart converging on the plane 10 ahead, 30° view. The left half is the left eye's view
/// squeezed to half width (each pixel the mean of two columns), the right half the right
/// eye's. Each green cylinder of the lattice is seen by the eye at E where the line from E
/// through it meets the convergence plane: the front row (z = 10, on that plane) in the same
/// place in both halves, the rows behind shifted apart by 0.2 (1 − 10/z) on the plane.
#[test]
fn side_by_side_3d_tv_frame_puts_each_eyes_view_in_its_half() {
    // A strip of the frame along a row just above the horizon, where the green cylinders
    // stand against the sky; full views 1920 wide, so that even the farthest cylinders are
    // more than a squeezed pixel wide.
    let (width, height) = (1920, 64);
    let picture = render_file(
        &scene("3d-tv-side-by-side"),
        &["--width", "1920", "--height", "64", "--spp", "1"],
    );
    assert_eq!(picture.size, (width, height));
    let camera = Camera::standard(30.0, width, height);
    let row = 28;
    let s = camera.direction(0.0, row as f64).y;
    let half = width / 2;
    for (eye, offset) in [(-0.1, 0), (0.1, half)] {
        let e = DVec3::new(eye, 0.0, 0.0);
        for x in [-1.0, -1.0 / 3.0, 1.0 / 3.0, 1.0] {
            for z in [10.0, 20.0, 30.0, 40.0] {
                let p = DVec3::new(x, s * z, z);
                let image = e + (10.0 / (p - e).z) * (p - e);
                let (column, _) = camera.pixel(image);
                let squeezed = ((column - 0.5) / 2.0).round() as usize;
                let c = picture.rgb(offset + squeezed, row);
                assert!(
                    is_green(c),
                    "the eye at x = {eye} should see the green cylinder at x = {x}, z = {z} \
                     at column {} of the frame, which is {c}",
                    offset + squeezed
                );
            }
        }
    }
}

/// Where the ray from `origin` along the unit direction `d` first meets the sphere (`centre`,
/// `radius`) from outside: the distance along it.
fn sphere_hit(origin: DVec3, d: DVec3, centre: DVec3, radius: f64) -> Option<f64> {
    let oc = origin - centre;
    let b = oc.dot(d);
    let c = oc.length_squared() - radius * radius;
    let disc = b * b - c;
    (disc >= 0.0 && -b - disc.sqrt() > 0.0).then(|| -b - disc.sqrt())
}

/// scenes/autostereogram.toml: a black-and-white random-dot autostereogram of the lattice and
/// a ball. By Thimbleby, Inglis and Witten's construction (docs/SCENE_FORMAT.md), the two
/// pixels s(z) = (1 − μz) E / (2 − μz) apart about a pixel that sees depth z (mapped
/// linearly from 1 at near = 6 to 0 at far = 45, μ = 1/3, E = 180 pixels) have the same
/// colour. So in the sky (beyond far) every dot repeats 90 pixels on, and across the ball
/// (radius 0.5 at (0.4, −0.3, 7), its depth along the view direction worked out here for each
/// pixel of a 24° view) dots repeat at the ball's own, shorter, separation.
#[test]
fn autostereogram_dots_repeat_at_the_separation_of_each_depth() {
    let (width, height) = (600, 450);
    let picture = render_file(
        &scene("autostereogram"),
        &["--width", "600", "--height", "450", "--spp", "1"],
    );
    let camera = Camera::standard(24.0, width, height);
    let dot = |x: usize, y: usize| {
        let c = picture.rgb(x, y);
        assert!(
            c.x == c.y && c.y == c.z && (c.x == 0.0 || c.x == 1.0),
            "({x}, {y}) is {c}, not a black or white dot"
        );
        c.x
    };
    let (eyes, mu, near, far) = (180.0, 0.3333, 6.0, 45.0);
    let separation = |depth: f64| {
        let z = ((far - depth) / (far - near)).clamp(0.0, 1.0);
        (1.0 - mu * z) * eyes / (2.0 - mu * z)
    };
    // The top row sees only the sky.
    for x in 0..width - 90 {
        assert_eq!(
            dot(x, 0),
            dot(x + 90, 0),
            "sky dots {x} and {} differ",
            x + 90
        );
    }
    // Rows across the ball: each pair (l, l + s) whose midpoint sees the ball well inside its
    // outline.
    let (centre, radius) = (DVec3::new(0.4, -0.3, 7.0), 0.5);
    let (_, cy) = camera.pixel(centre);
    let depth_at = |x: f64, y: usize| {
        let d = camera.direction(x, y as f64).normalize();
        sphere_hit(DVec3::ZERO, d, centre, 0.8 * radius)
            .map(|_| sphere_hit(DVec3::ZERO, d, centre, radius).unwrap() * d.z)
    };
    let (mut same, mut pairs) = (0, 0);
    for y in (cy as usize - 40)..(cy as usize + 40) {
        for l in 0..width {
            // The midpoint's separation, found from that of a point about halfway.
            let Some(guess) = depth_at(l as f64 + 36.0, y) else {
                continue;
            };
            let Some(depth) = depth_at(l as f64 + separation(guess) / 2.0, y) else {
                continue;
            };
            let s = separation(depth).round() as usize;
            if l + s < width {
                pairs += 1;
                same += usize::from(dot(l, y) == dot(l + s, y));
            }
        }
    }
    // Dots at any other distance match by chance, half of the time.
    assert!(
        pairs > 5000 && same as f64 > 0.98 * pairs as f64,
        "{same} of {pairs} dot pairs across the ball match"
    );
}

/// The rays from `start` towards each of `targets`, traced through the example scene `name`.
#[track_caller]
fn trace_towards(name: &str, start: DVec3, targets: &[DVec3]) -> Vec<Traced> {
    trace_towards_with(name, start, targets, &[])
}

/// [`trace_towards`] with more options (`--set KEY=VALUE`).
#[track_caller]
fn trace_towards_with(
    name: &str,
    start: DVec3,
    targets: &[DVec3],
    options: &[&str],
) -> Vec<Traced> {
    let rays: Vec<String> = targets
        .iter()
        .enumerate()
        .map(|(k, &t)| ray(k, start, t - start))
        .collect();
    let traced = trace_with(name, &rays, options);
    assert_eq!(traced.len(), targets.len());
    traced
}

/// Whether two points (or directions) agree to `tolerance`.
#[track_caller]
fn assert_near(what: &str, got: DVec3, expected: DVec3, tolerance: f64) {
    assert!(
        (got - expected).length() < tolerance,
        "{what}: {got}, expected {expected}"
    );
}

/// A ray leaving a lens: where and in which direction.
type Exit = (DVec3, DVec3);

/// §3's closed forms for a lens of centre `c` and radius `r` met at `p` along `d`: Eqs 5–6
/// (Luneburg), 7–8 (Eaton) and 9–10 (Maxwell fisheye).
fn perfect_lens(kind: &str, c: DVec3, r: f64, p: DVec3, d: DVec3) -> Exit {
    let d = d.normalize();
    let big_r = c - p;
    match kind {
        "Luneburg" => (c + r * d, big_r.normalize()),
        "Eaton" => (p + 2.0 * (big_r - big_r.dot(d) * d), -d),
        "Maxwell-fisheye" => {
            let rh = big_r.normalize();
            (c + big_r, 2.0 * d.dot(rh) * rh - d)
        }
        _ => panic!("{kind}"),
    }
}

/// The direction of a traced ray after its `k`th point (towards the next, or its last
/// direction).
fn leaving(ray: &Traced, k: usize) -> DVec3 {
    match ray.points.get(k + 1) {
        Some(next) => (next.position - ray.points[k].position).normalize(),
        None => ray.direction.normalize(),
    }
}

/// Whether a colour is grey (the floor, lit by white light), or an exact multiple of the sky's.
fn is_grey(c: DVec3) -> bool {
    c.x == c.y && c.y == c.z
}

/// scenes/fig6-perfect-imaging-lenses.toml (Fig. 6): a Luneburg lens (bottom left), an Eaton
/// lens (top) and a Maxwell-fisheye lens (bottom right), radius 0.3, in front of the lattice.
/// Lines of sight from the camera leave each lens where and as Eqs 5–10 say. In the picture:
/// the Eaton lens retro-reflects, so every pixel of it sees the floor behind the camera (grey)
/// and none the lattice; the Luneburg and Maxwell-fisheye lenses show an inverted view — the
/// pixels of their upper parts whose rays leave steeply downwards see the floor, and those of
/// the lower parts whose rays leave steeply upwards see the sky.
#[test]
fn fig6_perfect_imaging_lenses_map_rays_by_eqs_5_to_10() {
    let name = "fig6-perfect-imaging-lenses";
    let lenses = [
        ("Luneburg", DVec3::new(-0.5, -0.3, 6.0)),
        ("Eaton", DVec3::new(0.0, 0.4, 6.0)),
        ("Maxwell-fisheye", DVec3::new(0.5, -0.3, 6.0)),
    ];
    let r = 0.3;
    let offsets = [
        DVec3::new(0.1, 0.15, 0.0),
        DVec3::new(-0.2, -0.05, 0.0),
        DVec3::new(0.05, -0.25, 0.0),
    ];
    let targets: Vec<DVec3> = lenses
        .iter()
        .flat_map(|&(_, c)| offsets.iter().map(move |&o| c + o))
        .collect();
    let traced = trace_towards(name, DVec3::ZERO, &targets);
    for (k, ray) in traced.iter().enumerate() {
        let (kind, c) = lenses[k / offsets.len()];
        let object = format!("{kind} lens");
        let d = targets[k].normalize();
        let p = sphere_hit(DVec3::ZERO, d, c, r).unwrap() * d;
        let (exit, out) = perfect_lens(kind, c, r, p, d);
        assert_eq!(
            ray.points[1].object.as_deref(),
            Some(object.as_str()),
            "{ray:?}"
        );
        assert_near(&format!("{object}: entry"), ray.points[1].position, p, 1e-9);
        assert_near(
            &format!("{object}: exit"),
            ray.points[2].position,
            exit,
            1e-9,
        );
        assert_near(
            &format!("{object}: direction"),
            leaving(ray, 2),
            out.normalize(),
            1e-9,
        );
    }

    let (width, height) = (160, 120);
    let camera = Camera::standard(20.0, width, height);
    let picture = render(name, width, height);
    let mut seen: HashMap<(&str, &str), usize> = HashMap::new();
    for (x, y) in picture.pixels() {
        let d = camera.direction(x as f64, y as f64).normalize();
        for &(kind, c) in &lenses {
            // Pixels well inside the lens's outline.
            if sphere_hit(DVec3::ZERO, d, c, 0.95 * r).is_none() {
                continue;
            }
            let p = sphere_hit(DVec3::ZERO, d, c, r).unwrap() * d;
            assert_eq!(picture.object(x, y), format!("{kind} lens"), "({x}, {y})");
            let (exit, out) = perfect_lens(kind, c, r, p, d);
            let out = out.normalize();
            if lenses
                .iter()
                .any(|&(_, other)| other != c && sphere_hit(exit, out, other, r).is_some())
            {
                continue; // into another lens
            }
            let level = out.x.hypot(out.z);
            let colour = picture.rgb(x, y);
            let upper = p.y > c.y;
            if kind == "Eaton" || out.y < -0.5 * level {
                assert!(
                    is_grey(colour),
                    "{kind} lens at ({x}, {y}) shows {colour}, not the floor"
                );
                *seen
                    .entry((kind, if upper { "floor above" } else { "floor below" }))
                    .or_default() += 1;
            } else if out.y > 0.5 * level {
                let sky = SKY * DEFAULT_TRANSMISSION_COEFFICIENT;
                assert!(
                    (colour - sky).length() < 1e-6,
                    "{kind} lens at ({x}, {y}) shows {colour}, not the sky {sky}"
                );
                *seen
                    .entry((kind, if upper { "sky above" } else { "sky below" }))
                    .or_default() += 1;
            }
        }
    }
    let count = |kind, what| seen.get(&(kind, what)).copied().unwrap_or(0);
    for kind in ["Luneburg", "Maxwell-fisheye"] {
        assert!(
            count(kind, "floor above") > 100
                && count(kind, "sky below") > 100
                && count(kind, "floor below") == 0
                && count(kind, "sky above") == 0,
            "the {kind} lens is not upside down: {seen:?}"
        );
    }
    assert!(count("Eaton", "floor above") + count("Eaton", "floor below") > 1000);
}

/// Snell's law: the unit direction `d` refracted at a surface with unit normal `n` (on the side
/// `d` comes from) from index n₁ into n₂, `eta` = n₁/n₂; `None` beyond the critical angle.
fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = -n.dot(d);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| (eta * d + (eta * cos_i - k.sqrt()) * n).normalize())
}

/// Šarbort and Tyc's GGRIN lens (§3.1, Eqs 11–15) of centre `c` and radius `radius`, with
/// r = r′ = ∞ and the angle `phi`, and an invisible core of radius `core` (§3.2): where a ray
/// met at `p` along `d` leaves the lens, and its direction.
fn ggrin_infinite(c: DVec3, radius: f64, phi: f64, core: f64, p: DVec3, d: DVec3) -> Exit {
    let d = d.normalize();
    let pv = p - c;
    let p_d = d.dot(pv);
    let e = (pv - p_d * d).normalize();
    let p_e = e.dot(pv);
    // Q: where the ray would leave undeviated; with r = r′ = ∞, A lies infinitely far back
    // and I infinitely far ahead, so atan2(a_d, a_e) = −π/2 and atan2(i_d, i_e) = π/2.
    let (q_d, q_e) = (-p_d, p_e);
    if p_e < core * radius {
        return (c + q_d * d + q_e * e, d);
    }
    let beta = -PI / 2.0 - PI / 2.0 + phi;
    let d2 = d * beta.cos() + e * beta.sin();
    let e2 = -d * beta.sin() + e * beta.cos();
    (c + q_d * d2 + q_e * e2, d2)
}

/// The same lens with the index ratio `ratio` at its surface (§3.3): refraction in, the map,
/// refraction out.
fn ggrin_with_surface(
    c: DVec3,
    radius: f64,
    phi: f64,
    core: f64,
    ratio: f64,
    p: DVec3,
    d: DVec3,
) -> Exit {
    let inside = refract(d.normalize(), (p - c).normalize(), 1.0 / ratio).unwrap();
    let (exit, out) = ggrin_infinite(c, radius, phi, core, p, inside);
    let out = refract(out, -(exit - c).normalize(), ratio).unwrap();
    (exit, out)
}

/// scenes/fig9-ggrin-lens.toml (Fig. 9): a GGRIN lens with r = r′ = ∞ and φ = 170°, radius 1
/// at (0, 0, 8). By Eq 13 every ray turns by β = φ − 180° = −10°, i.e. 10° towards the lens's
/// centre whatever its impact parameter (an axicon). Lines of sight leave where Eqs 11–15 say,
/// and every pixel of the lens whose ray leaves past the lattice shows the sky or the floor
/// that the turned ray meets.
#[test]
fn fig9_ggrin_lens_turns_every_ray_10_degrees_towards_its_centre() {
    let name = "fig9-ggrin-lens";
    let (c, radius, phi) = (DVec3::new(0.0, 0.0, 8.0), 1.0, 170f64.to_radians());
    let targets = [
        DVec3::new(0.3, 0.2, 8.0),
        DVec3::new(-0.7, 0.1, 8.0),
        DVec3::new(0.05, -0.9, 8.0),
        DVec3::new(-0.4, -0.5, 7.5),
    ];
    for (ray, &target) in trace_towards(name, DVec3::ZERO, &targets)
        .iter()
        .zip(&targets)
    {
        let d = target.normalize();
        let p = sphere_hit(DVec3::ZERO, d, c, radius).unwrap() * d;
        let (exit, out) = ggrin_infinite(c, radius, phi, 0.0, p, d);
        assert_eq!(ray.points[1].object.as_deref(), Some("GGRIN lens"));
        assert_near("entry", ray.points[1].position, p, 1e-9);
        assert_near("exit", ray.points[2].position, exit, 1e-9);
        assert_near("direction", leaving(ray, 2), out, 1e-9);
        // 10° towards the centre.
        assert!((angle(d, out).to_degrees() - 10.0).abs() < 1e-9);
        let outwards = (p - c) - (p - c).dot(d) * d;
        assert!(out.dot(outwards) < 0.0, "{out} turns away from the centre");
    }

    let (width, height) = (160, 120);
    let camera = Camera::standard(20.0, width, height);
    let picture = render(name, width, height);
    let mut seen = HashMap::new();
    for (x, y) in picture.pixels() {
        let d = camera.direction(x as f64, y as f64).normalize();
        if sphere_hit(DVec3::ZERO, d, c, 0.98 * radius).is_none() {
            continue;
        }
        assert_eq!(picture.object(x, y), "GGRIN lens");
        let p = sphere_hit(DVec3::ZERO, d, c, radius).unwrap() * d;
        let (exit, out) = ggrin_infinite(c, radius, phi, 0.0, p, d);
        if let Some(sees) = Lattice::Standard.sees(exit, out) {
            let t = DEFAULT_TRANSMISSION_COEFFICIENT;
            assert_shows(&format!("pixel ({x}, {y})"), picture.rgb(x, y), sees, t);
            *seen.entry(sees).or_insert(0) += 1;
        }
    }
    for what in ["sky", "floor", "red", "green", "blue"] {
        assert!(seen.get(what).copied().unwrap_or(0) > 500, "{seen:?}");
    }
}

/// Checks the colour of every pixel for which `line` gives the ray that leaves the optics in
/// front of the lattice (its start, direction and the fraction of light passed on) and the
/// lattice studio's view along it is clear-cut; returns the pixels checked and what each saw.
#[track_caller]
fn assert_view(
    picture: &Picture,
    lattice: Lattice,
    mut line: impl FnMut(usize, usize) -> Option<(DVec3, DVec3, f64)>,
) -> Vec<(usize, usize, &'static str)> {
    let mut seen = Vec::new();
    for (x, y) in picture.pixels() {
        let Some((origin, d, transmission)) = line(x, y) else {
            continue;
        };
        if let Some(what) = lattice.sees(origin, d) {
            assert_shows(
                &format!("pixel ({x}, {y})"),
                picture.rgb(x, y),
                what,
                transmission,
            );
            seen.push((x, y, what));
        }
    }
    seen
}

/// How many of the pixels `seen` (from [`assert_view`]) saw each thing.
fn tally(seen: &[(usize, usize, &'static str)]) -> HashMap<&'static str, usize> {
    let mut counts = HashMap::new();
    for &(_, _, what) in seen {
        *counts.entry(what).or_insert(0) += 1;
    }
    counts
}

/// The multi-focal lens of Figs 11 and 12 (radius 1 at (0, 0, 8), r = r′ = ∞, φ = 90°,
/// R_t = 0.3) with the surface index ratio `ratio`, seen by `camera`: lines of sight leave as
/// §3's maps say, and each pixel of the lens shows what its ray meets after it. Returns the
/// number of pixels checked whose ray passes within R_t of the centre (inside the lens),
/// and of those how many differ from the lattice seen without the lens, dimmed by the lens's
/// transmission coefficient.
#[track_caller]
fn assert_multifocal_lens(name: &str, camera: Camera, ratio: f64) -> (usize, usize) {
    let (c, radius, phi, core) = (DVec3::new(0.0, 0.0, 8.0), 1.0, PI / 2.0, 0.3);
    let map = |p: DVec3, d: DVec3| ggrin_with_surface(c, radius, phi, core, ratio, p, d);
    let targets = [
        DVec3::new(0.1, 0.1, 8.0),
        DVec3::new(-0.2, 0.05, 8.0),
        DVec3::new(0.5, 0.3, 8.0),
        DVec3::new(-0.6, -0.4, 8.0),
        DVec3::new(0.0, 0.85, 8.0),
    ];
    let traced = trace_towards(name, camera.position, &targets);
    for (ray, &target) in traced.iter().zip(&targets) {
        let d = (target - camera.position).normalize();
        let p = camera.position + sphere_hit(camera.position, d, c, radius).unwrap() * d;
        let (exit, out) = map(p, d);
        assert_eq!(ray.points[1].object.as_deref(), Some("multi-focal lens"));
        assert_near("entry", ray.points[1].position, p, 1e-9);
        assert_near("exit", ray.points[2].position, exit, 1e-9);
        assert_near("direction", leaving(ray, 2), out, 1e-9);
    }

    let picture = render_file(
        &scene(name),
        &[
            "--width",
            &camera.width.to_string(),
            "--height",
            &camera.height.to_string(),
            "--spp",
            "1",
            "--aov",
            "object",
        ],
    );
    let control = render_text(
        &format!(
            "studio = \"lattice\"\n[camera]\nposition = {}\nview_direction = {}\n",
            toml_vector(camera.position),
            toml_vector(camera.forward)
        ),
        camera.width,
        camera.height,
    );
    let (mut core_pixels, mut changed) = (0, 0);
    let seen = tally(&assert_view(&picture, Lattice::Standard, |x, y| {
        let d = camera.direction(x as f64, y as f64).normalize();
        sphere_hit(camera.position, d, c, 0.98 * radius)?;
        assert_eq!(picture.object(x, y), "multi-focal lens");
        let p = camera.position + sphere_hit(camera.position, d, c, radius).unwrap() * d;
        let inside = refract(d, (p - c).normalize(), 1.0 / ratio).unwrap();
        if line_distance(c, p, inside) < core * radius {
            core_pixels += 1;
            let dimmed = control.rgb(x, y) * DEFAULT_TRANSMISSION_COEFFICIENT;
            changed += usize::from((picture.rgb(x, y) - dimmed).length() > 1e-5);
        }
        let (exit, out) = map(p, d);
        Some((exit, out, DEFAULT_TRANSMISSION_COEFFICIENT))
    }));
    let count = |what| seen.get(what).copied().unwrap_or(0);
    assert!(
        count("sky") > 1000
            && count("floor") > 1000
            && count("red") + count("green") + count("blue") > 50,
        "{seen:?}"
    );
    (core_pixels, changed)
}

/// scenes/fig11a-multifocal-lens.toml (Fig. 11(a)): the multi-focal lens, a GGRIN lens with
/// r = r′ = ∞ and φ = 90° round an invisible sphere, from the standard camera. Lines of sight
/// leave it as Eqs 11–15 and §3.2 say, every pixel of it shows what its ray meets, and those
/// whose straight line passes within R_t of the centre show exactly what the lattice studio
/// shows there without the lens: an empty tunnel along the view direction.
#[test]
fn fig11a_multifocal_lens_has_an_empty_tunnel_along_the_view() {
    let (core, changed) = assert_multifocal_lens(
        "fig11a-multifocal-lens",
        Camera::standard(20.0, 160, 120),
        1.0,
    );
    assert!(
        core > 500 && changed == 0,
        "{changed} of {core} tunnel pixels differ"
    );
}

/// scenes/fig11b-multifocal-lens.toml (Fig. 11(b)): the same lens seen from (2, 0, 0) along
/// (−0.2, 0, 1), the paper's second view: the tunnel follows the new view direction, the
/// pixels whose lines of sight pass within R_t of the centre showing the lattice studio as
/// that camera sees it without the lens.
#[test]
fn fig11b_multifocal_lens_tunnel_follows_the_view_direction() {
    let camera = Camera::new(
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(-0.2, 0.0, 1.0),
        DVec3::Y,
        20.0,
        160,
        120,
    );
    let (core, changed) = assert_multifocal_lens("fig11b-multifocal-lens", camera, 1.0);
    assert!(
        core > 500 && changed == 0,
        "{changed} of {core} tunnel pixels differ"
    );
}

/// scenes/fig12-index-ratio.toml (Fig. 12): the view of Fig. 11(b) with the index ratio 1.5 at
/// the lens's surface: rays are refracted by Snell's law into the lens before the map (or the
/// invisible core) and out after it (§3.3). Every pixel of the lens shows what its ray so
/// refracted meets, and the rays through the core no longer show the scene behind unchanged:
/// the centre is no empty tunnel.
#[test]
fn fig12_index_ratio_refracts_at_the_lens_surface() {
    let camera = Camera::new(
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(-0.2, 0.0, 1.0),
        DVec3::Y,
        20.0,
        160,
        120,
    );
    let (core, changed) = assert_multifocal_lens("fig12-index-ratio", camera, 1.5);
    assert!(
        core > 500 && changed > core / 2,
        "only {changed} of {core} pixels through the core differ from the view without the lens"
    );
}

/// A ray from `origin` along the unit direction `d` through a homogeneous ball (centre `c`,
/// radius `r`, index ratio `n`) by Snell's law: where it enters, where it leaves and its
/// direction then; `None` if it misses the ball.
fn glass_ball(origin: DVec3, d: DVec3, c: DVec3, r: f64, n: f64) -> Option<(DVec3, DVec3, DVec3)> {
    let p = origin + sphere_hit(origin, d, c, r)? * d;
    let inside = refract(d, (p - c).normalize(), 1.0 / n)?;
    // The chord: the far intersection of the line from p along `inside`.
    let exit = p + 2.0 * (c - p).dot(inside) * inside;
    let out = refract(inside, -(exit - c).normalize(), n)?;
    Some((p, exit, out))
}

/// The pixels of a picture that see a ball (centre `c`, radius `r`) well inside its outline,
/// sorted into those above and below the line from the camera to its centre.
fn ball_pixels(camera: &Camera, c: DVec3, r: f64, x: usize, y: usize) -> Option<DVec3> {
    let d = camera.direction(x as f64, y as f64).normalize();
    sphere_hit(camera.position, d, c, 0.98 * r).map(|_| d)
}

/// Asserts that a ball lens whose centre is seen at row `cy` shows the view upside down: of
/// the pixels `seen` (from [`assert_view`]), those that see the sky all lie below its
/// centre, and most that see the floor above it.
#[track_caller]
fn assert_inverted(seen: &[(usize, usize, &str)], cy: f64) {
    let count = |what, upper: bool| {
        seen.iter()
            .filter(|&&(_, y, w)| w == what && ((y as f64) < cy) == upper)
            .count()
    };
    assert!(
        count("sky", true) == 0
            && count("sky", false) > 1000
            && count("floor", true) > 1000
            && count("floor", false) < count("floor", true) / 10,
        "not inverted: sky {} above and {} below the centre, floor {} and {}",
        count("sky", true),
        count("sky", false),
        count("floor", true),
        count("floor", false)
    );
}

/// scenes/glass-ball.toml: a glass ball (n = 1.5, radius 0.6 at (0, −0.2, 6), transmission
/// 0.96 at each surface) in front of the lattice. Every pixel of the ball shows what its line
/// of sight, refracted by Snell's law into and out of the ball, meets, dimmed by 0.96²; and
/// the picture in it is inverted, like a thick lens's: the sky is seen only through its lower
/// half and the floor mostly through its upper half.
#[test]
fn glass_ball_shows_an_inverted_view_by_snells_law() {
    let (c, r, n) = (DVec3::new(0.0, -0.2, 6.0), 0.6, 1.5);
    let camera = Camera::standard(20.0, 160, 120);
    let picture = render("glass-ball", 160, 120);
    let (_, cy) = camera.pixel(c);
    let seen = assert_view(&picture, Lattice::Standard, |x, y| {
        let d = ball_pixels(&camera, c, r, x, y)?;
        assert_eq!(picture.object(x, y), "glass ball");
        let (_, exit, out) = glass_ball(DVec3::ZERO, d, c, r, n).unwrap();
        Some((exit, out, 0.96 * 0.96))
    });
    assert_inverted(&seen, cy);
}

/// A ray that meets the gradient-index ball (centre `c`, radius `radius`) of index
/// n = 1.3 − 0.3 (r/R)² (1 at the surface, as outside, so not refracted there) at `p` along
/// the unit direction `d`, followed through it by integrating the ray equation here
/// (dr/dτ = q, dq/dτ = n ∇n, q = n dr/ds; classical Runge–Kutta steps of 10⁻³): where it
/// leaves and its direction then.
fn parabolic_index_ball(c: DVec3, radius: f64, p: DVec3, d: DVec3) -> Exit {
    let r2 = radius * radius;
    let force = |r: DVec3| {
        let rho2 = (r - c).length_squared() / r2;
        (1.3 - 0.3 * rho2) * (-0.6 / r2) * (r - c)
    };
    let step = |r: DVec3, q: DVec3, h: f64| {
        let (k1r, k1q) = (q, force(r));
        let (k2r, k2q) = (q + 0.5 * h * k1q, force(r + 0.5 * h * k1r));
        let (k3r, k3q) = (q + 0.5 * h * k2q, force(r + 0.5 * h * k2r));
        let (k4r, k4q) = (q + h * k3q, force(r + h * k3r));
        (
            r + h / 6.0 * (k1r + 2.0 * k2r + 2.0 * k3r + k4r),
            q + h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q),
        )
    };
    let h = 1e-3;
    let (mut r, mut q) = step(p, d, h);
    loop {
        let (r1, q1) = step(r, q, h);
        if (r1 - c).length() >= radius {
            // Where within this step the ray reaches the surface, by bisection.
            let (mut lo, mut hi) = (0.0, h);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if (step(r, q, mid).0 - c).length() < radius {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let (exit, q) = step(r, q, hi);
            return (exit, q.normalize());
        }
        (r, q) = (r1, q1);
    }
}

/// scenes/gradient-index-table.toml: a ball lens of radius 0.6 at (0, −0.2, 6) whose index
/// profile, given as a table, is n = 1.3 − 0.3 (r/R)² (each entry is that formula, so its
/// spline is that parabola). Lines of sight leave it where the ray equation, integrated here,
/// says; every pixel of it shows what its ray then meets; and like a thick converging lens
/// it shows the view inverted: the sky only through its lower half, the floor mostly through
/// its upper half.
#[test]
fn gradient_index_table_lens_follows_the_ray_equation() {
    let name = "gradient-index-table";
    let lens = "parabolic gradient-index lens";
    let (c, radius) = (DVec3::new(0.0, -0.2, 6.0), 0.6);
    let targets = [
        DVec3::new(0.0, 0.1, 6.0),
        DVec3::new(0.3, -0.5, 6.0),
        DVec3::new(-0.45, 0.0, 6.0),
        DVec3::new(0.1, -0.7, 6.0),
    ];
    for (ray, &target) in trace_towards(name, DVec3::ZERO, &targets)
        .iter()
        .zip(&targets)
    {
        let d = target.normalize();
        let p = sphere_hit(DVec3::ZERO, d, c, radius).unwrap() * d;
        let (exit, out) = parabolic_index_ball(c, radius, p, d);
        let on = ray.on(lens);
        let k = ray
            .points
            .iter()
            .rposition(|q| q.object.as_deref() == Some(lens))
            .unwrap();
        assert_near("entry", on[0], p, 1e-9);
        assert_near("exit", on[on.len() - 1], exit, 1e-7);
        assert_near("direction", leaving(ray, k), out, 1e-7);
    }

    let camera = Camera::standard(20.0, 160, 120);
    let picture = render(name, 160, 120);
    let (_, cy) = camera.pixel(c);
    let seen = assert_view(&picture, Lattice::Standard, |x, y| {
        let d = ball_pixels(&camera, c, radius, x, y)?;
        assert_eq!(picture.object(x, y), lens);
        let p = sphere_hit(DVec3::ZERO, d, c, radius).unwrap() * d;
        let (exit, out) = parabolic_index_ball(c, radius, p, d);
        Some((exit, out, DEFAULT_TRANSMISSION_COEFFICIENT))
    });
    assert_inverted(&seen, cy);
}

/// The `k`th of `rays` start points of a bundle of radius `radius` about `start` along `axis`
/// (docs/SCENE_FORMAT.md, `[[ray_trajectory]]`: Vogel's sunflower, r = radius √((k + ½)/n),
/// k golden angles round, right-handed about the axis from its first perpendicular, here
/// `first`).
fn sunflower(start: DVec3, axis: DVec3, first: DVec3, radius: f64, k: usize, rays: usize) -> DVec3 {
    let golden = PI * (3.0 - 5f64.sqrt());
    let second = axis.normalize().cross(first);
    let r = radius * ((k as f64 + 0.5) / rays as f64).sqrt();
    let a = k as f64 * golden;
    start + r * (a.cos() * first + a.sin() * second)
}

/// Whether some pixel within `reach` pixels of (x, y) sees the object `name`, in a colour
/// within 1e-6 of `colour`.
fn sees_near(picture: &Picture, (x, y): (f64, f64), reach: i64, name: &str, colour: DVec3) -> bool {
    let (x, y) = (x.round() as i64, y.round() as i64);
    (-reach..=reach).any(|dy| {
        (-reach..=reach).any(|dx| {
            let (px, py) = (x + dx, y + dy);
            px >= 0
                && py >= 0
                && (px as usize) < picture.size.0
                && (py as usize) < picture.size.1
                && picture.object(px as usize, py as usize) == name
                && (picture.rgb(px as usize, py as usize) - colour).length() < 1e-6
        })
    })
}

/// scenes/trajectories-glass-ball.toml: thirty parallel rays along +x from the disc of radius
/// 0.9 about (−4, 0, 6) (Vogel's sunflower pattern) through a glass ball (n = 1.5, radius 1
/// at (0, 0, 6)). Each trajectory enters and leaves the ball where Snell's law says; the rays
/// cross the axis behind the ball, the innermost close to the paraxial focus
/// n R / (2 (n − 1)) = 1.5 from the centre and the outer ones ever closer to the ball
/// (spherical aberration); and the camera above sees the trajectories drawn in red.
#[test]
fn trajectories_glass_ball_show_spherical_aberration() {
    let path = scene("trajectories-glass-ball");
    let rays = trace_file(&path);
    assert_eq!(rays.len(), 30);
    let (c, r, n) = (DVec3::new(0.0, 0.0, 6.0), 1.0, 1.5);
    let start = DVec3::new(-4.0, 0.0, 6.0);
    let mut crossings = Vec::new();
    for (k, ray) in rays.iter().enumerate() {
        assert_near(
            "start",
            ray.points[0].position,
            sunflower(start, DVec3::X, DVec3::Y, 0.9, k, 30),
            1e-12,
        );
        let (entry, exit, out) = glass_ball(ray.points[0].position, DVec3::X, c, r, n).unwrap();
        assert_eq!(ray.points[1].object.as_deref(), Some("glass ball"));
        assert_near("entry", ray.points[1].position, entry, 1e-9);
        assert_near("exit", ray.points[2].position, exit, 1e-9);
        assert_near("direction", leaving(ray, 2), out, 1e-9);
        // Where the ray (in a plane through the axis) crosses the axis y = 0, z = 6.
        let off = DVec3::new(0.0, exit.y, exit.z - 6.0);
        let across = DVec3::new(0.0, out.y, out.z);
        let t = -off.dot(across) / across.length_squared();
        crossings.push((
            (ray.points[0].position - start).length(),
            exit.x + t * out.x,
        ));
    }
    crossings.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(
        (1.45..1.5).contains(&crossings[0].1),
        "the innermost ray crosses the axis {} from the centre",
        crossings[0].1
    );
    assert!(
        crossings.windows(2).all(|w| w[1].1 < w[0].1),
        "{crossings:?}"
    );

    // The camera above and behind sees each trajectory's first segment, halfway to the ball.
    let camera = Camera::new(
        DVec3::new(0.0, 3.0, -4.0),
        DVec3::new(0.0, -0.3, 1.0),
        DVec3::Y,
        40.0,
        640,
        480,
    );
    let picture = render_file(
        &path,
        &[
            "--width", "640", "--height", "480", "--spp", "1", "--aov", "object",
        ],
    );
    for ray in &rays {
        let p = ray.points[0].position + DVec3::new(1.5, 0.0, 0.0);
        assert!(
            sees_near(&picture, camera.pixel(p), 1, "parallel bundle", DVec3::X),
            "the trajectory through {p} is not drawn in red at {:?}",
            camera.pixel(p)
        );
    }
}

/// scenes/trajectories-luneburg-focus.toml: two bundles of twelve parallel rays along +z into
/// two Luneburg lenses of radius 0.5, at (∓0.7, 0, 6), the left by the closed form and the
/// right by integrating its index profile n = √(2 − (r/R)²). Every ray leaves from the far
/// pole C + R ẑ towards C − P (Eqs 5–6), P where it entered; the left lens's trajectories
/// jump across along the chord, the right's follow curved paths, each point of which lies on
/// the ellipse the ray equation gives for this profile, r(τ) = C + (P − C) cos(τ/R) +
/// R d̂ sin(τ/R). The camera sees the bundles in their colours.
#[test]
fn trajectories_luneburg_focus_on_the_far_pole() {
    let path = scene("trajectories-luneburg-focus");
    let rays = trace_file(&path);
    assert_eq!(rays.len(), 24);
    let radius = 0.5;
    for ray in &rays {
        let (lens, c, arrival) = if ray.trajectory.contains("closed-form") {
            (
                "closed-form Luneburg lens",
                DVec3::new(-0.7, 0.0, 6.0),
                "chord",
            )
        } else {
            (
                "integrated Luneburg lens",
                DVec3::new(0.7, 0.0, 6.0),
                "curved",
            )
        };
        let start = ray.points[0].position;
        assert!(
            (start - DVec3::new(c.x, 0.0, 4.0)).length() < 0.45,
            "{start} is outside the bundle"
        );
        let p = start + sphere_hit(start, DVec3::Z, c, radius).unwrap() * DVec3::Z;
        let on = ray.on(lens);
        assert_eq!(on.len(), 2, "{ray:?}");
        assert_near("entry", on[0], p, 1e-9);
        assert_near("exit", on[1], c + radius * DVec3::Z, 1e-9);
        let k = ray
            .points
            .iter()
            .rposition(|q| q.object.as_deref() == Some(lens))
            .unwrap();
        assert_eq!(ray.points[k].arrival, arrival);
        assert_near("direction", leaving(ray, k), (c - p).normalize(), 1e-9);
        // The points inside: on the ellipse through P along ẑ.
        let (a, b) = (p - c, radius * DVec3::Z);
        for q in &ray.points[2..k] {
            let v = q.position - c;
            // v = α a + β b in the plane of a and b.
            let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
            let det = aa * bb - ab * ab;
            let alpha = (v.dot(a) * bb - v.dot(b) * ab) / det;
            let beta = (v.dot(b) * aa - v.dot(a) * ab) / det;
            assert!(
                (alpha * a + beta * b - v).length() < 1e-9
                    && (alpha * alpha + beta * beta - 1.0).abs() < 1e-9,
                "{} is off the ellipse of the ray from {p}",
                q.position
            );
        }
        assert!(arrival == "chord" || k > 3, "{ray:?}");
    }
    // Each bundle, halfway to its lens, drawn in its colour.
    let camera = Camera::new(
        DVec3::new(2.5, 2.5, 1.5),
        DVec3::new(-2.5, -2.5, 4.5),
        DVec3::Y,
        35.0,
        640,
        480,
    );
    let picture = render_file(
        &path,
        &[
            "--width", "640", "--height", "480", "--spp", "1", "--aov", "object",
        ],
    );
    for ray in &rays {
        let (colour, name) = if ray.trajectory.contains("closed-form") {
            (
                DVec3::new(1.0, 0.1, 0.0),
                "bundle into the closed-form lens",
            )
        } else {
            (DVec3::new(1.0, 0.8, 0.0), "bundle into the integrated lens")
        };
        let q = ray.points[0].position + 0.75 * DVec3::Z;
        assert!(
            sees_near(&picture, camera.pixel(q), 1, name, colour),
            "{name} is not drawn at {q}"
        );
    }
}

/// scenes/lenslet-array.toml: 60 × 40 glass balls (n = 1.5, radius 0.02, transmission 0.96),
/// touching on a square grid of pitch 0.04 centred on (0, −0.2, 4). Every pixel of the
/// picture (which the array fills) sees through one ball — refracted by Snell's law into and
/// out of it, dimmed by 0.96² — or between the balls straight through, and shows what that
/// ray then meets. Each ball shows its own small inverted image: the sky is seen only
/// through the lower halves of the balls, the floor mostly through the upper halves.
#[test]
fn lenslet_array_balls_each_show_an_inverted_image() {
    let (width, height) = (320, 240);
    let camera = Camera::standard(20.0, width, height);
    let picture = render("lenslet-array", width, height);
    let (r, n, pitch) = (0.02, 1.5, 0.04);
    let centre =
        |i: i64, j: i64| DVec3::new(-1.18 + pitch * i as f64, -0.98 + pitch * j as f64, 4.0);
    // The balls near where a line crosses the plane z = 4.
    let near = |o: DVec3, d: DVec3| {
        let q = o + ((4.0 - o.z) / d.z) * d;
        let (i0, j0) = (
            ((q.x + 1.18) / pitch).round() as i64,
            ((q.y + 0.98) / pitch).round() as i64,
        );
        let mut balls = Vec::new();
        for i in (i0 - 3).max(0)..=(i0 + 3).min(59) {
            for j in (j0 - 3).max(0)..=(j0 + 3).min(39) {
                balls.push(centre(i, j));
            }
        }
        balls
    };
    let mut upper = HashMap::new();
    let seen = assert_view(&picture, Lattice::Standard, |x, y| {
        let d = camera.direction(x as f64, y as f64).normalize();
        let hits: Vec<(f64, DVec3)> = near(DVec3::ZERO, d)
            .into_iter()
            .filter_map(|c| sphere_hit(DVec3::ZERO, d, c, r).map(|t| (t, c)))
            .collect();
        let Some(&(_, c)) = hits.iter().min_by(|a, b| a.0.total_cmp(&b.0)) else {
            // Between the balls.
            let grazing = near(DVec3::ZERO, d)
                .into_iter()
                .any(|c| line_distance(c, DVec3::ZERO, d) < r * 1.01);
            return (!grazing).then_some((DVec3::ZERO, d, 1.0));
        };
        if line_distance(c, DVec3::ZERO, d) > 0.98 * r {
            return None; // the ball's rim
        }
        let (entry, exit, out) = glass_ball(DVec3::ZERO, d, c, r, n).unwrap();
        // Rays that leave the ball into another one, or along the array, are not followed.
        let into_another = near(exit, out).into_iter().any(|other| {
            other != c
                && line_distance(other, exit, out) < 1.01 * r
                && (other - exit).dot(out) > 0.0
        });
        if into_another || out.z < 0.2 {
            return None;
        }
        // Above or below the ball's centre, leaving out a band round it.
        if (entry.y - c.y).abs() > 0.25 * r {
            upper.insert((x, y), entry.y > c.y);
        }
        Some((exit, out, 0.96 * 0.96))
    });
    let count = |what, up| {
        seen.iter()
            .filter(|&&(x, y, w)| w == what && upper.get(&(x, y)) == Some(&up))
            .count()
    };
    let (sky_above, sky_below) = (count("sky", true), count("sky", false));
    let (floor_above, floor_below) = (count("floor", true), count("floor", false));
    assert!(
        sky_above == 0 && sky_below > 5000 && floor_above > 5000 && floor_below < floor_above / 10,
        "not inverted: sky {sky_above} above and {sky_below} below the balls' centres, floor \
         {floor_above} and {floor_below}"
    );
    let through = picture
        .pixels()
        .filter(|&(x, y)| {
            let d = camera.direction(x as f64, y as f64).normalize();
            near(DVec3::ZERO, d)
                .iter()
                .all(|&c| line_distance(c, DVec3::ZERO, d) > r)
        })
        .count();
    assert!(through > 5000, "{through} pixels see between the balls");
}

/// Checks the object and depth AOVs of every pixel against the spheres `spheres` (object name,
/// centre, radius) worked out here: a pixel whose line of sight from `camera` meets one of
/// them (clear of its rim) sees the nearest at its distance; one whose line of sight passes
/// clear of all of them sees none of them. Returns how many pixels saw each sphere's name.
#[track_caller]
fn assert_spheres_seen(
    picture: &Picture,
    camera: &Camera,
    spheres: &[(&str, DVec3, f64)],
) -> HashMap<String, usize> {
    let names: Vec<&str> = spheres.iter().map(|s| s.0).collect();
    let mut counts = HashMap::new();
    for (x, y) in picture.pixels() {
        let d = camera.direction(x as f64, y as f64).normalize();
        let nearest = |scale: f64| {
            spheres
                .iter()
                .filter_map(|&(name, c, r)| {
                    sphere_hit(camera.position, d, c, scale * r).map(|t| (t, name))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
        };
        let seen = picture.object(x, y);
        match (nearest(0.99), nearest(1.0), nearest(1.01)) {
            (Some(inner), Some((t, name)), _) if inner.1 == name => {
                assert_eq!(seen, name, "pixel ({x}, {y})");
                let depth = picture.depth(x, y);
                assert!(
                    (depth / t - 1.0).abs() < 1e-6,
                    "pixel ({x}, {y}) sees the {name} {depth} away, not {t}"
                );
                *counts.entry(name.to_string()).or_insert(0) += 1;
            }
            (_, _, None) => assert!(!names.contains(&seen), "pixel ({x}, {y}) sees the {seen}"),
            _ => {} // a rim
        }
    }
    counts
}

/// scenes/sphere-array.toml: a 5 × 4 × 3 array, spacing (0.3, 0, 0), (0, 0.35, 0) and
/// (0, 0, 1.2) in the scene's frame, of a red ball (radius 0.06) and a white one (radius
/// 0.03, at (0.09, 0.09, 0) from it), the pair turned 15° about the vertical (right-handed,
/// so the white ball moves to (0.0869, 0.09, −0.0233)) and moved to (−0.6, −0.7, 4). Every
/// pixel sees the balls where these numbers put them, at their distances, and no ball
/// elsewhere.
#[test]
fn sphere_array_places_every_pair_on_its_grid() {
    let (width, height) = (320, 240);
    let camera = Camera::standard(20.0, width, height);
    let picture = render("sphere-array", width, height);
    let turn = 15f64.to_radians();
    let white = DVec3::new(0.09 * turn.cos(), 0.09, -0.09 * turn.sin());
    let mut spheres = Vec::new();
    for i in 0..5 {
        for j in 0..4 {
            for k in 0..3 {
                let red = DVec3::new(
                    -0.6 + 0.3 * i as f64,
                    -0.7 + 0.35 * j as f64,
                    4.0 + 1.2 * k as f64,
                );
                spheres.push(("pairs/red", red, 0.06));
                spheres.push(("pairs/white", red + white, 0.03));
            }
        }
    }
    let counts = assert_spheres_seen(&picture, &camera, &spheres);
    assert!(
        counts["pairs/red"] > 5000 && counts["pairs/white"] > 1000,
        "{counts:?}"
    );
}

/// scenes/mirror.toml: a mirror (reflection 0.9) in the plane x = 0.6, from z = 3 to 9 and
/// from the floor (y = −1) up to y = 1.2, beside the lattice. Every pixel whose line of sight
/// meets it sees the mirror there and shows, dimmed to 0.9, what the line of sight reflected
/// by r = d − 2 (d·n) n meets — among it the lattice's mirror image; every other pixel
/// shows the studio seen straight.
#[test]
fn mirror_shows_the_lattices_mirror_image() {
    let camera = Camera::standard(20.0, 160, 120);
    let picture = render("mirror", 160, 120);
    let mut reflected = std::collections::HashSet::new();
    let seen = assert_view(&picture, Lattice::Standard, |x, y| {
        let d = camera.direction(x as f64, y as f64).normalize();
        let t = 0.6 / d.x;
        let p = t * d;
        let inside = t > 0.0 && (3.0..=9.0).contains(&p.z) && (-1.0..=1.2).contains(&p.y);
        let margin = t > 0.0
            && (2.99..=9.01).contains(&p.z)
            && (-1.01..=1.21).contains(&p.y)
            && !((3.01..=8.99).contains(&p.z) && (-0.99..=1.19).contains(&p.y));
        if margin {
            return None;
        }
        if inside {
            assert_eq!(picture.object(x, y), "mirror", "pixel ({x}, {y})");
            reflected.insert((x, y));
            Some((p, DVec3::new(-d.x, d.y, d.z), 0.9))
        } else {
            Some((DVec3::ZERO, d, 1.0))
        }
    });
    let mirrored_lattice = seen
        .iter()
        .filter(|&&(x, y, w)| reflected.contains(&(x, y)) && !["sky", "floor"].contains(&w))
        .count();
    assert!(
        reflected.len() > 3000 && mirrored_lattice > 300,
        "{} pixels see the mirror, {mirrored_lattice} of them the lattice",
        reflected.len()
    );
}

// ------------------------------------------------------------------------------------------
// §4–6: METATOYs
// ------------------------------------------------------------------------------------------

/// A symmetric 3 × 3 matrix from its rows.
fn metric(rows: [[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(&rows)
}

/// Refraction at a metric interface (§4.1), worked out from Fermat's condition directly:
/// for a ray with direction `d` in the metric `g` meeting a surface with unit normal `n`, the
/// outgoing direction e in the metric `h` has the tangential part of h e equal to that of
/// the incident covector ±g d / √|dᵀ g d| (− for negative refraction), so that
/// h e = k + λ n, and eᵀ h e = 1 (Eqs 19–26): a quadratic in λ, whose root with e on the far
/// side is the ray. `Err` with the reflected direction where there is none (total internal
/// reflection, the root on the near side of the same condition in `g`).
fn metric_refract(d: DVec3, g: DMat3, h: DMat3, n: DVec3, negative: bool) -> Result<DVec3, DVec3> {
    let sign = if negative { -1.0 } else { 1.0 };
    let k = sign * (g * d) / d.dot(g * d).abs().sqrt();
    let side = d.dot(n).signum();
    let solve = |m: DMat3, wanted: f64| {
        let mi = m.inverse();
        let (a, b, c) = (n.dot(mi * n), k.dot(mi * n), k.dot(mi * k) - 1.0);
        let disc = b * b - a * c;
        if disc < 0.0 {
            return None;
        }
        [(-b + disc.sqrt()) / a, (-b - disc.sqrt()) / a]
            .into_iter()
            .map(|lambda| mi * (k + lambda * n))
            .find(|e| e.dot(n).signum() == wanted)
    };
    match solve(h, side) {
        Some(e) => Ok(e),
        None => Err(solve(g, -side).expect("a reflected ray")),
    }
}

/// The METATOY window of `studio = "metatoy-window"`: the parallelogram from (−1.5, −0.98, 10)
/// spanning 3 along x and 2 along y, outward normal +z, framed by cylinders of radius 0.025.
const WINDOW: (DVec3, DVec3) = (DVec3::new(-1.5, -0.98, 10.0), DVec3::new(1.5, 1.02, 10.0));

/// Checks every pixel of a picture of a METATOY-window scene from the standard camera (20°):
/// a pixel whose line of sight meets the window (clear of its frame) sees the window and shows
/// what the ray that `law` gives for the point and unit direction where it meets it (start,
/// direction, fraction of light) meets among the lattice, floor and sky; a pixel whose line
/// of sight passes clear of the window and frame shows the floor or sky it meets. Returns the
/// pixels through the window and what each saw.
#[track_caller]
fn assert_window_view(
    picture: &Picture,
    law: impl Fn(DVec3, DVec3) -> Option<(DVec3, DVec3, f64)>,
) -> Vec<(usize, usize, &'static str)> {
    let camera = Camera::standard(20.0, picture.size.0, picture.size.1);
    let (lo, hi) = WINDOW;
    let margin = 0.04;
    let mut through = std::collections::HashSet::new();
    let seen = assert_view(picture, Lattice::Metatoy, |x, y| {
        let d = camera.direction(x as f64, y as f64).normalize();
        let p = (10.0 / d.z) * d;
        let within = |m: f64| p.x > lo.x + m && p.x < hi.x - m && p.y > lo.y + m && p.y < hi.y - m;
        if within(margin) {
            assert_eq!(picture.object(x, y), "window", "pixel ({x}, {y})");
            through.insert((x, y));
            // Rays that leave the window along it, to its frame, are not followed.
            law(p, d).filter(|&(q, e, _)| {
                let corners = [
                    lo,
                    DVec3::new(hi.x, lo.y, 10.0),
                    hi,
                    DVec3::new(lo.x, hi.y, 10.0),
                ];
                (0..4).all(|k| {
                    capped_cylinder_hit(q, e.normalize(), corners[k], corners[(k + 1) % 4], 0.03)
                        .is_none()
                })
            })
        } else if !within(-margin) {
            Some((DVec3::ZERO, d, 1.0))
        } else {
            None
        }
    });
    seen.into_iter()
        .filter(|&(x, y, _)| through.contains(&(x, y)))
        .collect()
}

/// The counts of what the pixels through the window saw, checked to include the lattice.
#[track_caller]
fn assert_lattice_through_window(seen: &[(usize, usize, &'static str)], at_least: usize) {
    let counts = tally(seen);
    let lattice: usize = ["red", "green", "blue"]
        .iter()
        .map(|c| counts.get(c).copied().unwrap_or(0))
        .sum();
    assert!(
        lattice >= at_least,
        "{lattice} pixels see the lattice through the window: {counts:?}"
    );
}

/// A rotation by `angle` (right-handed) about the z axis.
fn rotate_z(v: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    DVec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// scenes/metatoy-window.toml: TIM's "METATOY science" scene, its window a ray-rotating sheet
/// (Dr TIM's 60°, `angle_deg = -60`, transmission 0.96). A ray crossing the sheet keeps its
/// component along the normal and has the rest turned by 60°, clockwise seen facing the
/// oncoming light (docs/SCENE_FORMAT.md): rays from the camera, crossing along +z, turn by
/// −60° about +z. Every pixel of the window shows what its line of sight so turned meets —
/// the lattice turned by 60° — and the pixels round it the floor and sky.
#[test]
fn metatoy_window_rotates_rays_by_60_degrees() {
    let picture = render("metatoy-window", 160, 120);
    let seen = assert_window_view(&picture, |p, d| {
        Some((p, rotate_z(d, -60f64.to_radians()), 0.96))
    });
    assert_lattice_through_window(&seen, 200);
}

/// A metric interface on the window (inside, the camera's side, `g`; outside `h`): the
/// transmitted ray, dimmed by 0.96, or the totally internally reflected one, not dimmed.
fn window_metric(
    g: DMat3,
    h: DMat3,
    negative: bool,
) -> impl Fn(DVec3, DVec3) -> Option<(DVec3, DVec3, f64)> {
    move |p, d| {
        Some(match metric_refract(d, g, h, DVec3::Z, negative) {
            Ok(e) => (p, e, 0.96),
            Err(r) => (p, r, 1.0),
        })
    }
}

/// scenes/fig14a-metric-interface-n10.toml (Fig. 14(a)): the window as a metric interface with
/// the metric 100 I (index 10) on the camera's side and Euclidean space behind. By Fermat's
/// condition rays transmit only within asin(1/10) = 5.74° of the normal, where they spread over
/// the whole half-space behind; every other ray is totally internally reflected, losslessly,
/// back to the sky and floor behind the camera. Every pixel of the window shows what the ray
/// so refracted or reflected meets, and the lattice is seen only in the central disc.
#[test]
fn fig14a_metric_interface_n10_reflects_outside_a_central_disc() {
    let picture = render("fig14a-metric-interface-n10", 160, 120);
    let law = window_metric(
        metric([[100.0, 0.0, 0.0], [0.0, 100.0, 0.0], [0.0, 0.0, 100.0]]),
        DMat3::IDENTITY,
        false,
    );
    let seen = assert_window_view(&picture, &law);
    let camera = Camera::standard(20.0, 160, 120);
    let critical = 0.1f64.asin();
    let (mut reflected, mut lattice) = (0, 0);
    for &(x, y, what) in &seen {
        let off = angle(camera.direction(x as f64, y as f64), DVec3::Z);
        if off > critical {
            reflected += 1;
        }
        if !["sky", "floor"].contains(&what) {
            lattice += 1;
            assert!(
                off < critical,
                "pixel ({x}, {y}) sees the lattice {off} rad off the axis"
            );
        }
    }
    assert!(
        reflected > 3000 && lattice > 10,
        "{reflected} reflected, {lattice} see the lattice"
    );
}

/// The points where the rays `rays` (from [`trace_towards`]) leave the window's law, and the
/// direction they leave in.
fn after_window(rays: &[Traced]) -> Vec<(DVec3, DVec3)> {
    rays.iter()
        .map(|ray| {
            assert_eq!(ray.points[1].object.as_deref(), Some("window"), "{ray:?}");
            (ray.points[1].position, leaving(ray, 1))
        })
        .collect()
}

/// Where the line from `p` along `d` meets the plane z = `z`.
fn at_z(p: DVec3, d: DVec3, z: f64) -> DVec3 {
    p + ((z - p.z) / d.z) * d
}

/// Points of the window round its middle, for lines of sight from the camera.
fn window_targets() -> Vec<DVec3> {
    [
        (0.3, 0.2),
        (-0.8, 0.5),
        (1.1, -0.6),
        (-0.2, -0.7),
        (0.05, 0.9),
    ]
    .iter()
    .map(|&(x, y)| DVec3::new(x, y, 10.0))
    .collect()
}

/// scenes/fig14b-veselago-lens.toml (Fig. 14(b)): the window as a Veselago lens, the metric
/// interface between index −1 (the camera's side) and +1: negative refraction reverses the
/// tangential part of each ray, so every pixel of the window shows what the line of sight with
/// its tangential part reversed meets — the lattice's near part upright, its far part
/// inverted — and the lens images the camera, 10 in front of it, to the point 10 behind it:
/// every line of sight through the window passes through (0, 0, 20).
#[test]
fn fig14b_veselago_lens_images_the_camera_to_a_point_behind_it() {
    let name = "fig14b-veselago-lens";
    let rays = trace_towards(name, DVec3::ZERO, &window_targets());
    for (p, d) in after_window(&rays) {
        assert_near(
            "where the line of sight crosses z = 20",
            at_z(p, d, 20.0),
            DVec3::new(0.0, 0.0, 20.0),
            1e-9,
        );
    }
    let picture = render(name, 160, 120);
    let seen = assert_window_view(
        &picture,
        window_metric(DMat3::IDENTITY, DMat3::IDENTITY, true),
    );
    assert_lattice_through_window(&seen, 200);
}

/// Eq 39 of the paper, generalised confocal lenslet arrays with â = ẑ, û = x̂, v̂ = â × û = ŷ
/// and no offsets, for a ray travelling along â (meeting array 1 first).
fn gcla(d: DVec3, eta_u: f64, eta_v: f64) -> DVec3 {
    (DVec3::new(d.x / d.z / eta_u, d.y / d.z / eta_v, 0.0) + DVec3::Z).normalize()
}

/// scenes/gcla-window-eta-minus-1.toml: the window as generalised confocal lenslet arrays with
/// η_u = η_v = −1 (Eq 39): like the Veselago lens, every line of sight has its tangential part
/// reversed, so every pixel of the window shows what that ray meets, every line of sight
/// through the window passes through (0, 0, 20), and the picture is that of
/// fig14b-veselago-lens.toml.
#[test]
fn gcla_window_eta_minus_1_shows_the_veselago_lens_view() {
    let name = "gcla-window-eta-minus-1";
    let rays = trace_towards(name, DVec3::ZERO, &window_targets());
    for (p, d) in after_window(&rays) {
        assert_near(
            "where the line of sight crosses z = 20",
            at_z(p, d, 20.0),
            DVec3::new(0.0, 0.0, 20.0),
            1e-9,
        );
    }
    let picture = render(name, 160, 120);
    let seen = assert_window_view(&picture, |p, d| Some((p, gcla(d, -1.0, -1.0), 0.96)));
    assert_lattice_through_window(&seen, 200);
    let veselago = render("fig14b-veselago-lens", 160, 120);
    let differ = picture
        .pixels()
        .filter(|&(x, y)| (picture.rgb(x, y) - veselago.rgb(x, y)).length() > 1e-4)
        .count();
    assert!(
        differ <= 10,
        "{differ} pixels differ from the Veselago lens's"
    );
}

/// scenes/gcla-window-eta-u-minus-half.toml: generalised confocal lenslet arrays with
/// η_u = −0.5 and η_v = −1: a horizontal slope s of a line of sight becomes s/η_u = −2s, a
/// vertical one −s (Eq 39), so the window images the camera astigmatically: lines of sight in
/// the horizontal plane through the camera cross the axis at z = 10 + 10/2 = 15, those in the
/// vertical plane at z = 20. Every pixel of the window shows what its line of sight so
/// redirected meets.
#[test]
fn gcla_window_eta_u_minus_half_focuses_horizontally_at_15_and_vertically_at_20() {
    let name = "gcla-window-eta-u-minus-half";
    let targets = [
        DVec3::new(0.4, 0.0, 10.0),
        DVec3::new(-1.2, 0.0, 10.0),
        DVec3::new(0.0, 0.5, 10.0),
        DVec3::new(0.0, -0.8, 10.0),
    ];
    let rays = trace_towards(name, DVec3::ZERO, &targets);
    for (k, (p, d)) in after_window(&rays).into_iter().enumerate() {
        let z = if k < 2 { 15.0 } else { 20.0 };
        assert_near(
            "the crossing of the axis",
            at_z(p, d, z),
            DVec3::new(0.0, 0.0, z),
            1e-9,
        );
    }
    let picture = render(name, 160, 120);
    let seen = assert_window_view(&picture, |p, d| Some((p, gcla(d, -0.5, -1.0), 0.96)));
    assert_lattice_through_window(&seen, 200);
}

/// scenes/fig14c-sheared-space.toml (Fig. 14(c)): the window as the interface between space
/// sheared by 45° (metric g = SᵀS, S: x′ = x + z, on the camera's side) and Euclidean space.
/// Fermat's condition then makes every ray leave along S d: the line of sight straight ahead
/// leaves 45° to the right. Every pixel of the window shows what its line of sight so refracted
/// meets.
#[test]
fn fig14c_sheared_space_turns_lines_of_sight_by_the_shear() {
    let g = metric([[1.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 2.0]]);
    let shear = |d: DVec3| DVec3::new(d.x + d.z, d.y, d.z).normalize();
    let name = "fig14c-sheared-space";
    let rays = trace_towards(name, DVec3::ZERO, &window_targets());
    for ((_, e), target) in after_window(&rays).into_iter().zip(window_targets()) {
        assert_near("direction", e, shear(target.normalize()), 1e-9);
    }
    let ahead = metric_refract(DVec3::Z, g, DMat3::IDENTITY, DVec3::Z, false).unwrap();
    assert_near(
        "straight ahead",
        ahead.normalize(),
        DVec3::new(1.0, 0.0, 1.0).normalize(),
        1e-12,
    );
    let picture = render(name, 160, 120);
    let seen = assert_window_view(&picture, window_metric(g, DMat3::IDENTITY, false));
    assert_lattice_through_window(&seen, 50);
}

/// scenes/phase-hologram-window.toml: the window as the phase hologram of a lens,
/// φ = −r²/(2f) with f = 5 about the middle of the pane, (0, 0.02, 10) (the window's
/// coordinates (1.5, 1) from its corner): the tangential part of each unit direction changes
/// by ∇φ = −(r − r₀)/f. Every pixel of the window shows what its line of sight so turned
/// meets, and, as a thin lens of focal length 5 does, the window images the camera 10 in front
/// of it to the point 10 behind it, mirrored in its axis: (0, 0.04, 20), paraxially (the lines
/// of sight pass within the hologram's aberration, ρ³/(2f²), of it).
#[test]
fn phase_hologram_window_images_like_a_lens_of_focal_length_5() {
    let name = "phase-hologram-window";
    let centre = DVec3::new(0.0, 0.02, 10.0);
    let law = move |p: DVec3, d: DVec3| {
        let t = DVec3::new(d.x, d.y, 0.0) - (p - centre) / 5.0;
        Some((p, t + (1.0 - t.length_squared()).sqrt() * DVec3::Z, 0.96))
    };
    let targets: Vec<DVec3> = [(0.1, 0.0), (-0.15, 0.1), (0.05, -0.2), (0.0, 0.17)]
        .iter()
        .map(|&(x, y)| centre + DVec3::new(x, y, 0.0))
        .collect();
    let rays = trace_towards(name, DVec3::ZERO, &targets);
    for ((p, d), target) in after_window(&rays).into_iter().zip(&targets) {
        let rho = (*target - centre).length();
        assert_near("direction", d, law(p, target.normalize()).unwrap().1, 1e-9);
        assert_near(
            "image of the camera",
            at_z(p, d, 20.0),
            DVec3::new(0.0, 0.04, 20.0),
            rho.powi(3) / 50.0 * 4.0,
        );
    }
    let picture = render(name, 160, 120);
    let seen = assert_window_view(&picture, law);
    assert_lattice_through_window(&seen, 200);
}

/// scenes/ray-flipping-window.toml: the window as a ray-flipping sheet whose flip axis is 90°
/// from its u direction (x), i.e. vertical: the horizontal component of each ray is reversed.
/// Every pixel of the window shows what its line of sight so flipped meets: the lattice
/// mirrored left to right.
#[test]
fn ray_flipping_window_mirrors_left_and_right() {
    let picture = render("ray-flipping-window", 160, 120);
    let seen = assert_window_view(&picture, |p, d| Some((p, DVec3::new(-d.x, d.y, d.z), 0.96)));
    assert_lattice_through_window(&seen, 200);
}

/// scenes/lorentz-window.toml: the window changes the direction of every ray as the rays of a
/// camera moving at β = (0, 0, 0.9) are changed (Eq 4). Every pixel of the window shows what
/// its line of sight so aberrated meets, the lattice squeezed towards the middle; round it the
/// view is the plain studio's.
#[test]
fn lorentz_window_aberrates_like_a_camera_moving_at_0_9c() {
    let beta = DVec3::new(0.0, 0.0, 0.9);
    let picture = render("lorentz-window", 160, 120);
    let seen = assert_window_view(&picture, |p, d| {
        Some((p, aberrate(d, beta).normalize(), 0.96))
    });
    assert_lattice_through_window(&seen, 50);
}

/// scenes/teleporting-window.toml: the window teleports every ray to the point with the same
/// surface coordinates on "teleporter exit", a parallelogram of the window's size 14 further
/// on (z = 24), with the same direction. Every pixel of the window shows what its line of
/// sight continued from there meets: the lattice's far half (z = 29 and 38) as from a camera
/// 14 tiles forwards, never its near rows.
#[test]
fn teleporting_window_shows_the_view_from_14_tiles_on() {
    let picture = render("teleporting-window", 160, 120);
    let seen = assert_window_view(&picture, |p, d| {
        let exit = p + DVec3::new(0.0, 0.0, 14.0);
        // Not where the exit lies within a red cylinder (they run through z = 24).
        (Lattice::Metatoy.distance("red", exit) > 0.03).then_some((exit, d, 0.96))
    });
    assert_lattice_through_window(&seen, 200);
}

/// A line of sight from `origin` along `d` through a sphere (centre `c`, radius `r`) of space
/// with the metric `g` inside and Euclidean space outside (§4, metric interfaces with
/// transmission 0.96): refracted in by Fermat's condition, straight inside (a homogeneous
/// metric's rays are straight lines), totally internally reflected (without loss) where it
/// cannot leave, refracted out. The ray that leaves, with the fraction of light it carries,
/// and the number of reflections.
fn metric_bubble(
    origin: DVec3,
    d: DVec3,
    c: DVec3,
    r: f64,
    g: DMat3,
) -> Option<(DVec3, DVec3, f64, usize)> {
    let mut p = origin + sphere_hit(origin, d, c, r)? * d;
    let mut e = match metric_refract(d, DMat3::IDENTITY, g, (p - c) / r, false) {
        Ok(e) => e,
        Err(reflected) => return Some((p, reflected, 1.0, 1)),
    };
    for reflections in 0..50 {
        // The far side of the sphere along the straight line.
        let q = p - 2.0 * (p - c).dot(e) / e.length_squared() * e;
        match metric_refract(e, g, DMat3::IDENTITY, (q - c) / r, false) {
            Ok(out) => return Some((q, out, 0.96 * 0.96, reflections)),
            Err(reflected) => (p, e) = (q, reflected),
        }
    }
    None
}

/// The pixels of a metric bubble (radius 0.6 at (0, 0, 6), in front of the lattice), from the
/// standard camera: each shows what its line of sight through the bubble meets. Returns how
/// many lines of sight were totally internally reflected on the way.
#[track_caller]
fn assert_metric_bubble(name: &str, object: &str, g: DMat3) -> usize {
    let (c, r) = (DVec3::new(0.0, 0.0, 6.0), 0.6);
    let camera = Camera::standard(20.0, 160, 120);
    let picture = render(name, 160, 120);
    let mut reflected = 0;
    let seen = assert_view(&picture, Lattice::Standard, |x, y| {
        let d = ball_pixels(&camera, c, r, x, y)?;
        assert_eq!(picture.object(x, y), object);
        let (exit, out, transmission, reflections) = metric_bubble(DVec3::ZERO, d, c, r, g)?;
        reflected += usize::from(reflections > 0);
        Some((exit, out, transmission))
    });
    let counts = tally(&seen);
    assert!(
        counts.get("sky").copied().unwrap_or(0) > 200
            && counts.get("floor").copied().unwrap_or(0) > 200,
        "{counts:?}"
    );
    reflected
}

/// scenes/fig15a-metric-bubble.toml (Fig. 15, top): a sphere of space with the paper's metric
/// g11 = 1, g12 = 0.2, g13 = 0, g22 = 1.2, g23 = −0.5, g33 = 0.5 inside, Euclidean outside.
/// Every pixel of it shows what its line of sight, refracted by Fermat's condition at both
/// surfaces and straight inside, meets; near the edge some lines of sight are totally
/// internally reflected inside first.
#[test]
fn fig15a_metric_bubble_refracts_by_fermats_principle() {
    let g = metric([[1.0, 0.2, 0.0], [0.2, 1.2, -0.5], [0.0, -0.5, 0.5]]);
    let reflected = assert_metric_bubble("fig15a-metric-bubble", "metric bubble", g);
    assert!(reflected > 20, "{reflected} totally internally reflected");
}

/// scenes/fig15b-minkowski-bubble.toml (Fig. 15, bottom): the same with the Minkowski-like
/// metric diag(−1, 1, 1) inside: every pixel of the sphere shows what its line of sight,
/// refracted in and out by Fermat's condition (normalised to eᵀ g e = 1 inside), meets.
#[test]
fn fig15b_minkowski_bubble_refracts_by_fermats_principle() {
    let g = metric([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    assert_metric_bubble("fig15b-minkowski-bubble", "Minkowski bubble", g);
}

/// The distance between the lines through `a` along `u` and through `b` along `v`.
fn line_line_distance(a: DVec3, u: DVec3, b: DVec3, v: DVec3) -> f64 {
    let n = u.cross(v);
    if n.length() < 1e-12 {
        return line_distance(b, a, u);
    }
    (b - a).dot(n.normalize()).abs()
}

/// scenes/trajectories-metatoy-window.toml: eight rays from (0, 0.02, 7) on a cone of
/// half-angle 8° about +z through the ray-rotating window (−60° about +z for rays crossing
/// along +z). Each meets the window 3 tan 8° from the cone's axis, leaves it with its
/// direction turned by −60° about +z, and so no longer meets the axis: it passes it at
/// 3 tan 8° sin 60°, all eight lines tangent to one circle (skew lines, a twisted bundle). The
/// camera above sees them drawn in magenta in front of the window.
#[test]
fn trajectories_metatoy_window_become_skew_lines() {
    let path = scene("trajectories-metatoy-window");
    let rays = trace_file(&path);
    assert_eq!(rays.len(), 8);
    let start = DVec3::new(0.0, 0.02, 7.0);
    let half = 8f64.to_radians();
    let rho = 3.0 * half.tan();
    let mut azimuths = Vec::new();
    for ray in &rays {
        assert_near("start", ray.points[0].position, start, 1e-12);
        let d = leaving(ray, 0);
        assert!(
            (angle(d, DVec3::Z) - half).abs() < 1e-12,
            "{d} is not on the cone"
        );
        azimuths.push(d.y.atan2(d.x));
        assert_eq!(ray.points[1].object.as_deref(), Some("window"));
        let p = ray.points[1].position;
        assert_near("window", p, start + (3.0 / d.z) * d, 1e-9);
        let out = leaving(ray, 1);
        assert_near("direction", out, rotate_z(d, -60f64.to_radians()), 1e-9);
        let miss = line_line_distance(p, out, start, DVec3::Z);
        assert!(
            (miss - rho * 60f64.to_radians().sin()).abs() < 1e-9,
            "the ray passes the axis at {miss}"
        );
    }
    azimuths.sort_by(f64::total_cmp);
    for w in azimuths.windows(2) {
        assert!((w[1] - w[0] - PI / 4.0).abs() < 1e-9, "{azimuths:?}");
    }
    let camera = Camera::new(
        DVec3::new(0.5, 8.0, 4.0),
        DVec3::new(-0.5, -8.0, 6.5),
        DVec3::Z,
        40.0,
        640,
        480,
    );
    let picture = render_file(
        &path,
        &[
            "--width", "640", "--height", "480", "--spp", "1", "--aov", "object",
        ],
    );
    for ray in &rays {
        let q = at_z(start, leaving(ray, 0), 8.5);
        assert!(
            sees_near(
                &picture,
                camera.pixel(q),
                1,
                "cone through the window",
                DVec3::new(1.0, 0.0, 1.0)
            ),
            "the trajectory through {q} is not drawn at {:?}",
            camera.pixel(q)
        );
    }
}

// ------------------------------------------------------------------------------------------
// Ideal thin lenses and the devices made of them
// ------------------------------------------------------------------------------------------

/// The textbook thin lens in vector form: a ray with direction `d` meeting an ideal thin lens
/// (principal point `principal`, optical axis `axis`, focal length `f`) at `s` keeps its
/// direction through the principal point and changes its slope by −(s − principal)/f, so that
/// parallel rays meet in the focal plane.
fn ideal_lens(d: DVec3, s: DVec3, principal: DVec3, axis: DVec3, f: f64) -> DVec3 {
    (d / d.dot(axis).abs() + (principal - s) / f).normalize()
}

/// The traced rays from `starts` along `directions` through the example scene `name`.
#[track_caller]
fn trace_rays(name: &str, rays: &[(DVec3, DVec3)]) -> Vec<Traced> {
    let tables: Vec<String> = rays
        .iter()
        .enumerate()
        .map(|(k, &(s, d))| ray(k, s, d))
        .collect();
    let traced = trace(name, &tables);
    assert_eq!(traced.len(), rays.len());
    traced
}

/// scenes/ideal-lenses.toml: three ideal imaging discs at z = 5, radius 0.45. Left, an ideal
/// thin lens with f = −1.5 about (−1, 0, 5): rays through its principal point go straight and
/// parallel rays leave as if from its front focal point (−1, 0, 3.5). Middle, a glens with
/// f₋ = −1, f₊ = 3 about (0, 0, 5): rays towards its nodal point N = P + (f₋ + f₊) ẑ =
/// (0, 0, 7) go straight, and rays parallel to the axis meet at F₊ = (0, 0, 8). Right, a
/// cylindrical lens with f = 3 and power along x about (0, 0, 5): parallel rays meet on the
/// focal line x = 0, z = 8, keeping their height. Every pixel of the discs shows what the
/// lines of sight these laws give meet.
#[test]
fn ideal_lenses_image_as_thin_lenses_and_a_glens() {
    let name = "ideal-lenses";
    let (lens, glens) = (DVec3::new(-1.0, 0.0, 5.0), DVec3::new(0.0, 0.0, 5.0));
    let nodal = DVec3::new(0.0, 0.0, 7.0);
    let cases = [
        // (start, direction, the point the ray must pass after the lens, or None to go straight)
        (
            DVec3::new(-1.2, 0.1, 3.0),
            DVec3::Z,
            Some(DVec3::new(-1.0, 0.0, 3.5)),
        ),
        (
            DVec3::new(-0.8, -0.25, 3.0),
            DVec3::Z,
            Some(DVec3::new(-1.0, 0.0, 3.5)),
        ),
        (
            DVec3::new(-1.3, 0.2, 3.0),
            lens - DVec3::new(-1.3, 0.2, 3.0),
            None,
        ),
        (
            DVec3::new(0.3, 0.2, 3.0),
            nodal - DVec3::new(0.3, 0.2, 3.0),
            None,
        ),
        (
            DVec3::new(-0.25, 0.1, 3.0),
            nodal - DVec3::new(-0.25, 0.1, 3.0),
            None,
        ),
        (
            DVec3::new(0.2, -0.1, 3.0),
            DVec3::Z,
            Some(DVec3::new(0.0, 0.0, 8.0)),
        ),
        (
            DVec3::new(-0.3, 0.25, 3.0),
            DVec3::Z,
            Some(DVec3::new(0.0, 0.0, 8.0)),
        ),
        (
            DVec3::new(1.2, 0.1, 3.0),
            DVec3::Z,
            Some(DVec3::new(0.0, 0.1, 8.0)),
        ),
        (
            DVec3::new(0.8, -0.3, 3.0),
            DVec3::Z,
            Some(DVec3::new(0.0, -0.3, 8.0)),
        ),
    ];
    let rays = trace_rays(name, &cases.iter().map(|c| (c.0, c.1)).collect::<Vec<_>>());
    for (ray, (start, d, through)) in rays.iter().zip(cases) {
        let (s, out) = (ray.points[1].position, leaving(ray, 1));
        assert!((s.z - 5.0).abs() < 1e-12, "{ray:?}");
        match through {
            Some(q) => {
                // Diverging: the line backwards; converging: forwards.
                assert!(
                    line_distance(q, s, out) < 1e-9,
                    "the ray from {start} does not pass {q}: {ray:?}"
                );
            }
            None => assert_near("undeviated", out, d.normalize(), 1e-9),
        }
    }

    // Every pixel of the discs: the laws above (the glens's for rays into its positive space:
    // d′ ∝ −(f₋/f₊) d + (d·ẑ/f₊)(N − S)).
    let camera = Camera::standard(30.0, 360, 200);
    let picture = render(name, 360, 200);
    let seen = assert_view(&picture, Lattice::Standard, |x, y| {
        let d = camera.direction(x as f64, y as f64).normalize();
        let s = (5.0 / d.z) * d;
        let (centre, object) = [
            (lens, "ideal thin lens"),
            (glens, "glens"),
            (DVec3::new(1.0, 0.0, 5.0), "cylindrical lens"),
        ]
        .into_iter()
        .find(|(c, _)| (s - *c).length() < 0.46)?;
        if (s - centre).length() > 0.44 {
            return None;
        }
        assert_eq!(picture.object(x, y), object, "pixel ({x}, {y})");
        let out = match object {
            "ideal thin lens" => ideal_lens(d, s, lens, DVec3::Z, -1.5),
            "glens" => (d / 3.0 + d.z / 3.0 * (nodal - s)).normalize(),
            _ => (DVec3::new(d.x / d.z - s.x / 3.0, d.y / d.z, 1.0)).normalize(),
        };
        Some((s, out, 0.96))
    });
    let counts = tally(&seen);
    assert!(
        counts.get("sky").copied().unwrap_or(0) > 5000
            && counts.get("floor").copied().unwrap_or(0) > 5000
            && ["red", "green", "blue"]
                .iter()
                .all(|c| counts.get(c).copied().unwrap_or(0) > 500),
        "{counts:?}"
    );
}

/// scenes/lens-star.toml: five ideal thin lenses (f = 1) meeting along the vertical axis
/// through (0, 0, 10), lens 1 towards +x, lens k turned by 72° (k − 1) about +y (right-handed).
/// The red trajectory is the
/// regular pentagon round the axis: it crosses each lens at a vertex 2 f tan(π/5) = 1.4531
/// from the axis (its inscribed circle, through its start, 2 f sin(π/5) from it), in the
/// plane y = 0, lens after lens; the perturbed trajectory, off that plane, also closes: after
/// five lenses each ray is back on its own path, so the second round retraces the first.
#[test]
fn lens_star_trajectories_close_after_one_round() {
    let path = scene("lens-star");
    let rays = trace_file(&path);
    assert_eq!(rays.len(), 2);
    let axis = DVec3::new(0.0, 0.0, 10.0);
    for ray in &rays {
        // Round and round until the limit of ten surfaces.
        assert_eq!(ray.end, "max-interactions", "{ray:?}");
        assert_eq!(ray.points.len(), 11, "{ray:?}");
        for k in 1..=5 {
            let lens = format!("lens star/lens {k}");
            assert_eq!(
                ray.points[k].object.as_deref(),
                Some(lens.as_str()),
                "{ray:?}"
            );
            assert_eq!(
                ray.points[k + 5].object.as_deref(),
                Some(lens.as_str()),
                "{ray:?}"
            );
            assert_near(
                "the second round",
                ray.points[k + 5].position,
                ray.points[k].position,
                1e-9,
            );
            // On lens k: at the angle −72° (k − 1) from +x about the axis (y up).
            let p = ray.points[k].position - axis;
            let expected = -72f64.to_radians() * (k - 1) as f64;
            let turn = (p.z.atan2(p.x) - expected).rem_euclid(2.0 * PI);
            assert!(
                turn.min(2.0 * PI - turn) < 1e-9,
                "{} is not on lens {k}",
                ray.points[k].position
            );
        }
    }
    let pentagon = &rays[0];
    let inscribed = (pentagon.points[0].position - axis).length();
    assert!(
        (inscribed - 2.0 * (PI / 5.0).sin()).abs() < 1e-4,
        "{inscribed}"
    );
    for q in &pentagon.points[1..] {
        let r = q.position - axis;
        assert!(
            r.y == 0.0 && (r.length() - 2.0 * (PI / 5.0).tan()).abs() < 1e-3,
            "{}",
            q.position
        );
    }
}

/// Asserts that the traced lines of sight `rays` that pass through a device (whose parts are
/// named `device/...`) and come out again leave along the lines they came on: outside space is
/// imaged to itself. Rays that end on a part of the device (an edge) or on one of the objects
/// `inside` it are left out; returns how many rays were checked.
#[track_caller]
fn assert_outside_imaged_to_itself(rays: &[Traced], device: &str, inside: &[&str]) -> usize {
    let prefix = format!("{device}/");
    let mut checked = 0;
    for ray in rays {
        let end = ray.last_object();
        if end.starts_with(&prefix) || inside.contains(&end) {
            continue;
        }
        let Some(last) = ray
            .points
            .iter()
            .rposition(|p| p.object.as_deref().is_some_and(|o| o.starts_with(&prefix)))
        else {
            continue;
        };
        let (start, d) = (ray.points[0].position, leaving(ray, 0));
        assert_near(
            "the direction out of the device",
            leaving(ray, last),
            d,
            1e-6,
        );
        assert!(
            line_distance(ray.points[last].position, start, d) < 1e-6,
            "the ray from {start} along {d} leaves the device from {}, off its line: {ray:?}",
            ray.points[last].position
        );
        checked += 1;
    }
    checked
}

/// The lines of sight from `eye` to a grid of points round `centre`, `half` across.
fn grid_targets(centre: DVec3, half: DVec3, n: usize) -> Vec<DVec3> {
    let mut targets = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (
                2.0 * i as f64 / (n - 1) as f64 - 1.0,
                2.0 * j as f64 / (n - 1) as f64 - 1.0,
            );
            targets.push(centre + DVec3::new(a * half.x, b * half.y, 0.0));
        }
    }
    targets
}

/// The distance between the segments from `p1` to `q1` and from `p2` to `q2` (Ericson,
/// Real-Time Collision Detection, 5.1.9).
fn segment_segment_distance(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(r));
    let (b, c) = (d1.dot(d2), d1.dot(r));
    let denom = a * e - b * b;
    let mut s = if denom > 1e-300 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    ((p1 + s * d1) - (p2 + t * d2)).length()
}

/// An ideal-lens cloak of the example scenes (a device named "cloak" with a ball inside its
/// lower inner pyramid), its geometry worked out from the scene file's numbers.
struct Cloak {
    scene: &'static str,
    eye: DVec3,
    camera: Camera,
    base: DVec3,
    /// The vertices outside space sees where they are: the base's and the top.
    outer: Vec<DVec3>,
    /// The lower and upper inner vertices' heights above the base, physical and in EM space.
    lower: (f64, f64),
    upper: (f64, f64),
    ball: (DVec3, f64),
}

impl Cloak {
    /// Where outside space sees a point of the lower inner pyramid. Seen from below, through
    /// the base alone, the cell is imaged by the base's ideal thin lens, whose principal point
    /// is the base's centre B (by symmetry): X′ = B + (X − B)/(1 + h/F), h the height above
    /// the base, with the focal length F that sees the lower inner vertex at h₁′ (ideal thin
    /// lenses image points projectively, along lines through the principal point). The cloak
    /// shows every cell alike from every direction, so this is how outside space sees it.
    fn seen_at(&self, p: DVec3) -> DVec3 {
        let (h1, h1e) = self.lower;
        let inverse_f = (h1 / h1e - 1.0) / h1;
        let h = p.y - self.base.y;
        self.base + (p - self.base) / (1.0 + h * inverse_f)
    }

    /// Every line between two vertices as outside space sees them.
    fn seen_segments(&self) -> Vec<(DVec3, DVec3)> {
        let mut vertices = self.outer.clone();
        vertices.push(self.base + self.lower.1 * DVec3::Y);
        vertices.push(self.base + self.upper.1 * DVec3::Y);
        let mut segments = Vec::new();
        for i in 0..vertices.len() {
            for j in i + 1..vertices.len() {
                segments.push((vertices[i], vertices[j]));
            }
        }
        segments
    }

    /// Lines of sight through a grid over the cloak leave it on the lines they came on; a line
    /// of sight aimed at where outside space sees a point of the ball ends on the ball, its last
    /// segment through that point; a line of sight through the ball above where it is seen
    /// misses it. In the picture, every pixel whose line of sight goes through the ball but
    /// clear of where the ball and the frames are seen shows what that straight line meets
    /// behind the cloak, dimmed only by the lenses.
    #[track_caller]
    fn check(&self) {
        let (centre, r) = self.ball;
        let targets = grid_targets(self.base + 0.8 * DVec3::Y, DVec3::new(0.8, 0.75, 0.0), 9);
        let rays = trace_towards(self.scene, self.eye, &targets);
        let through = assert_outside_imaged_to_itself(&rays, "cloak", &["cloaked ball"]);
        assert!(through > 30, "{through} lines of sight through the cloak");

        let inside = [
            centre,
            centre + DVec3::new(-0.12, 0.08, 0.05),
            centre + DVec3::new(0.15, -0.1, -0.05),
        ];
        let seen: Vec<DVec3> = inside.iter().map(|&p| self.seen_at(p)).collect();
        let hidden = centre + DVec3::new(0.0, 0.5 * r, 0.0);
        let d = (hidden - self.eye).normalize();
        assert!(sphere_hit(self.eye, d, centre, r).is_some());
        // Without the frames: the hexagonal cloak's front edge stands right in front of where
        // the ball is seen.
        let rays = trace_towards_with(
            self.scene,
            self.eye,
            &[&seen[..], &[hidden]].concat(),
            &["--set", "device.0.show_edges=false"],
        );
        for (ray, p) in rays.iter().zip(inside) {
            let n = ray.points.len();
            assert_eq!(ray.last_object(), "cloaked ball", "{ray:?}");
            let last = ray.points[n - 2].position;
            assert!(
                line_distance(p, last, ray.points[n - 1].position - last) < 1e-9,
                "the line of sight to {} ends on the ball off {p}: {ray:?}",
                self.seen_at(p)
            );
        }
        assert_ne!(rays[3].last_object(), "cloaked ball", "{:?}", rays[3]);

        // The picture without the frames (the cylinders along the lenses' edges), whose images
        // inside the cloak are magnified where the lenses image strongly.
        let picture = render_file(
            &scene(self.scene),
            &[
                "--width",
                &self.camera.width.to_string(),
                "--height",
                &self.camera.height.to_string(),
                "--spp",
                "1",
                "--aov",
                "object",
                "--set",
                "device.0.show_edges=false",
            ],
        );
        let segments = self.seen_segments();
        let squashed_top = self.seen_at(centre + r * DVec3::Y);
        let seen = assert_view(&picture, Lattice::Standard, |x, y| {
            let d = self.camera.direction(x as f64, y as f64).normalize();
            sphere_hit(self.eye, d, centre, 0.9 * r)?;
            let far = self.eye + 100.0 * d;
            let clear = segments
                .iter()
                .all(|&(a, b)| segment_segment_distance(self.eye, far, a, b) > 0.02)
                && segment_segment_distance(
                    self.eye,
                    far,
                    DVec3::new(centre.x, self.base.y, centre.z),
                    squashed_top,
                ) > r + 0.03;
            if !clear {
                return None;
            }
            assert!(
                picture.object(x, y).starts_with("cloak/"),
                "pixel ({x}, {y})"
            );
            Some((self.eye, d, -0.9))
        });
        assert!(
            seen.len() > 100,
            "{} pixels through the hidden ball",
            seen.len()
        );
    }
}

/// scenes/ideal-lens-cloak.toml: the tetrahedral ideal-lens cloak (height 2 on a base of
/// circumradius 4/3 at (0, −0.98, 7.5); inner vertices 2/3 and 4/3 up, the lower seen at
/// 1/15) hiding a white ball (radius 0.2667) on its base. Outside space is imaged to itself;
/// the ball is seen squashed to a tenth of its height, so lines of sight through where it is
/// miss it and show the lattice and floor behind, undistorted.
#[test]
fn ideal_lens_cloak_hides_the_ball_and_shows_whats_behind() {
    let base = DVec3::new(0.0, -0.98, 7.5);
    let radius = 4.0 / 3.0;
    let eye = DVec3::new(0.0, 0.5, 0.0);
    // The back vertex opposite the front direction (−z), the others 120° on.
    let mut outer: Vec<DVec3> = [0.0f64, 120.0, 240.0]
        .iter()
        .map(|a| base + radius * DVec3::new(a.to_radians().sin(), 0.0, a.to_radians().cos()))
        .collect();
    outer.push(base + 2.0 * DVec3::Y);
    let (h, h1, h2, h1e) = (2.0, 2.0 / 3.0, 4.0 / 3.0, 1.0 / 15.0);
    let h2e = h2 * h1e * (h1 - h) / (h1 * (h1e - h) - h2 * (h1e - h1));
    Cloak {
        scene: "ideal-lens-cloak",
        eye,
        camera: Camera::new(eye, DVec3::new(0.0, -0.12, 1.0), DVec3::Y, 30.0, 320, 240),
        base,
        outer,
        lower: (h1, h1e),
        upper: (h2, h2e),
        ball: (DVec3::new(0.0, -0.7133, 7.5), 0.2667),
    }
    .check();
}

/// scenes/polygonal-ideal-lens-cloak.toml: the hexagonal ideal-lens cloak (height 2 on a
/// regular hexagon of circumradius 1.4 about (0, −0.98, 7.5); inner vertices 0.7 and 1.3 up,
/// the lower seen at 0.007) hiding a white ball of radius 0.2 on its base: outside space is
/// imaged to itself, the ball is seen squashed to a hundredth of its height, and lines of
/// sight through where it is show what is behind the cloak.
#[test]
fn polygonal_ideal_lens_cloak_hides_the_ball_and_shows_whats_behind() {
    let base = DVec3::new(0.0, -0.98, 7.5);
    let eye = DVec3::new(0.0, 0.5, 0.0);
    let mut outer: Vec<DVec3> = (0..6)
        .map(|i| {
            let a = (60.0 * i as f64).to_radians();
            base + 1.4 * DVec3::new(a.sin(), 0.0, a.cos())
        })
        .collect();
    outer.push(base);
    outer.push(base + 2.0 * DVec3::Y);
    let (h, h1, h2, h1e) = (2.0, 0.7, 1.3, 0.007);
    let h2e = h2 * h1e * (h1 - h) / (h1 * (h1e - h) - h2 * (h1e - h1));
    Cloak {
        scene: "polygonal-ideal-lens-cloak",
        eye,
        camera: Camera::new(eye, DVec3::new(0.0, -0.12, 1.0), DVec3::Y, 30.0, 320, 240),
        base,
        outer,
        lower: (h1, h1e),
        upper: (h2, h2e),
        ball: (DVec3::new(0.0, -0.78, 7.5), 0.2),
    }
    .check();
}

/// scenes/four-pi-lens.toml: a 4π lens whose lens L1 would lie on the floor about
/// C = (0, −0.98, 7.5), facing up, an ideal thin lens of focal length f = 2 (−
/// `focal_length_outwards`), closed into a tetrahedron by the lenses R1 so that inside space
/// (the cell just above L1) is seen through them from every direction as L1 alone shows it: a
/// point X at height h above L1 at C + (X − C)/(1 − h/f) (the thin-lens image,
/// 1/o + 1/i = 1/f, on the line through the principal point). Lines of sight through the sides
/// aimed at those images of points of the white ball inside end on the ball, their last
/// segments through the points; one aimed at the image of a point just under the ball's top
/// ends on it although its straight line passes above the ball (the ball is seen magnified,
/// 1.1 times at its centre); and outside space, the lattice behind, is seen through the lens
/// as itself. L1 itself is not made (Dr TIM's default, `showL1` false), so the lines of sight
/// that end on the floor under it, through the open base (within its circumcircle, radius
/// 1.4), are left out of that check.
#[test]
fn four_pi_lens_shows_inside_space_as_its_floor_lens_does() {
    let name = "four-pi-lens";
    let eye = DVec3::new(0.0, 0.5, 0.0);
    let c = DVec3::new(0.0, -0.98, 7.5);
    let f = 2.0;
    let image = |x: DVec3| c + (x - c) / (1.0 - (x.y - c.y) / f);
    let (centre, r) = (DVec3::new(0.0, -0.78, 7.5), 0.15);
    let targets = grid_targets(c + 0.8 * DVec3::Y, DVec3::new(0.9, 0.75, 0.0), 9);
    let under_l1 = |ray: &Traced| {
        let end = ray.points[ray.points.len() - 1].position;
        ray.last_object() == "floor" && (end - c).with_y(0.0).length() < 1.4
    };
    let rays: Vec<Traced> = trace_towards(name, eye, &targets)
        .into_iter()
        .filter(|ray| !under_l1(ray))
        .collect();
    let through = assert_outside_imaged_to_itself(&rays, "4pi lens", &["ball inside"]);
    assert!(through > 30, "{through} lines of sight through the lens");

    let inside = [
        centre,
        centre + DVec3::new(0.08, 0.05, 0.03),
        centre + DVec3::new(-0.1, -0.05, -0.04),
        centre + DVec3::new(0.0, r - 0.01, 0.0),
    ];
    let seen: Vec<DVec3> = inside.iter().map(|&p| image(p)).collect();
    let straight = (seen[3] - eye).normalize();
    assert!(sphere_hit(eye, straight, centre, r).is_none());
    for (ray, p) in trace_towards(name, eye, &seen).iter().zip(inside) {
        let n = ray.points.len();
        assert_eq!(ray.last_object(), "ball inside", "{ray:?}");
        let last = ray.points[n - 2].position;
        assert!(
            ray.points[n - 2]
                .object
                .as_deref()
                .is_some_and(|o| o.starts_with("4pi lens/")),
            "{ray:?}"
        );
        assert!(
            line_distance(p, last, ray.points[n - 1].position - last) < 1e-9,
            "the line of sight to {} ends on the ball off {p}: {ray:?}",
            image(p)
        );
    }
}

/// scenes/lens-simplicial-complex.toml: Dr TIM's omnidirectional lens (a lens simplicial
/// complex: a tetrahedron on a triangular base cut into seven cells by two inner vertices, every
/// face an ideal thin lens), stood upright by its group's transform (a −90° turn about x, then
/// (0, −10.9, 10)): base (−1.5, −0.9, 8.9), (1, −0.9, 9), (0, −0.9, 10.5), inner vertices
/// (0, −0.3, 10) and (0, 0.3, 10), seen 0.2 higher, top (0, 1.1, 10). Outside space is seen
/// through it as itself. The lowest cell, and the ball in it, is seen as the base's lens shows
/// it: that lens images the lower inner vertex onto its virtual position, so its principal
/// point is where the line through the two meets the base, B = (0, −0.9, 10), and
/// 1/f = 1/0.8 − 1/0.6: a point X at height h above the base is seen at
/// B + (X − B)/(1 + h/f). Lines of sight aimed there end on the ball, their last segments
/// through X; and a line of sight aimed at the lower inner vertex's virtual position ends on
/// the frame at its physical position.
#[test]
fn lens_simplicial_complex_shows_its_cells_where_virtual_space_puts_them() {
    let name = "lens-simplicial-complex";
    let eye = DVec3::new(2.5, 1.0, 3.0);
    let b = DVec3::new(0.0, -0.9, 10.0);
    let inverse_f = 1.0 / 0.8 - 1.0 / 0.6;
    let seen_at = |x: DVec3| b + (x - b) / (1.0 + (x.y - b.y) * inverse_f);
    let targets = grid_targets(DVec3::new(-0.1, 0.1, 9.8), DVec3::new(1.0, 0.9, 0.0), 9);
    let rays = trace_towards(name, eye, &targets);
    let through = assert_outside_imaged_to_itself(
        &rays,
        "structure/omnidirectional lens",
        &["structure/ball"],
    );
    assert!(through > 20, "{through} lines of sight through the complex");

    let (centre, r) = (DVec3::new(-0.05, -0.7, 9.6), 0.1);
    let inside = [
        centre,
        centre + DVec3::new(0.05, 0.04, -0.03),
        centre + DVec3::new(-0.04, -0.05, 0.05),
    ];
    let lower = DVec3::new(0.0, -0.3, 10.0);
    assert_near(
        "the lower inner vertex's virtual position",
        seen_at(lower),
        DVec3::new(0.0, -0.1, 10.0),
        1e-12,
    );
    let targets: Vec<DVec3> = inside
        .iter()
        .map(|&p| seen_at(p))
        .chain([seen_at(lower)])
        .collect();
    let rays = trace_towards(name, eye, &targets);
    for (ray, p) in rays.iter().zip(inside.iter().chain([&lower])) {
        let n = ray.points.len();
        let last = ray.points[n - 2].position;
        assert!(
            line_distance(*p, last, ray.points[n - 1].position - last) < 1e-9,
            "the line of sight to {} does not end towards {p}: {ray:?}",
            seen_at(*p)
        );
    }
    for ray in &rays[..3] {
        assert_eq!(ray.last_object(), "structure/ball", "{ray:?}");
        assert!((ray.last() - centre).length() < r + 1e-9);
    }
    let frame = rays[3].last_object();
    assert!(
        frame.starts_with("structure/omnidirectional lens/edge")
            && (rays[3].last() - lower).length() < 0.03,
        "{rays:?}"
    );
}

/// scenes/platonic-lens.toml: a cubic Platonic lens (circumradius 1.2 about (0, 0, 6), the
/// cube's vertices (±1, ±1, ±1)/√3 read along the orthonormalised basis (1, 0, 0.3),
/// (0, 1, −0.2) and their cross product): for each of the cube's 12 edges, the triangle of the
/// edge and the centre is an ideal thin lens of focal length 0.5 with its principal point at
/// the centre. Every point where a line of sight meets the lens lies on one of those
/// triangles, and the ray leaves it as the thin-lens law says for that triangle's plane.
#[test]
fn platonic_lens_refracts_at_the_triangles_of_a_cubes_edges() {
    let name = "platonic-lens";
    let c = DVec3::new(0.0, 0.0, 6.0);
    let e1 = DVec3::new(1.0, 0.0, 0.3).normalize();
    let e2 = (DVec3::new(0.0, 1.0, -0.2) - DVec3::new(0.0, 1.0, -0.2).dot(e1) * e1).normalize();
    let e3 = e1.cross(e2);
    let vertex = |s: [f64; 3]| c + 1.2 / 3f64.sqrt() * (s[0] * e1 + s[1] * e2 + s[2] * e3);
    let mut triangles = Vec::new();
    for s in [
        [1.0, 1.0, 1.0],
        [-1.0, -1.0, 1.0],
        [-1.0, 1.0, -1.0],
        [1.0, -1.0, -1.0],
    ] {
        // Each edge joins a vertex to one differing in one sign; from these four vertices
        // (no two adjacent) the three flips reach all twelve edges.
        for k in 0..3 {
            let mut t = s;
            t[k] = -t[k];
            triangles.push((vertex(s), vertex(t)));
        }
    }
    let targets: Vec<DVec3> = [
        (0.3, 0.2, 0.0),
        (-0.5, 0.4, -0.5),
        (0.6, -0.7, 0.3),
        (-0.2, -0.3, 0.5),
        (0.9, 0.1, -0.2),
        (-0.8, -0.6, 0.1),
        (0.1, 0.8, 0.2),
    ]
    .iter()
    .map(|&(x, y, z)| c + DVec3::new(x, y, z))
    .collect();
    let rays = trace_towards(name, DVec3::ZERO, &targets);
    let mut crossings = 0;
    for ray in &rays {
        for k in 1..ray.points.len() {
            let point = &ray.points[k];
            if !point
                .object
                .as_deref()
                .is_some_and(|o| o.starts_with("platonic lens/lens"))
            {
                continue;
            }
            let s = point.position;
            let (a, b) = triangles
                .iter()
                .copied()
                .find(|&(a, b)| {
                    let n = (a - c).cross(b - c).normalize();
                    // In the plane and inside the triangle (c, a, b).
                    let inside = |p: DVec3, q: DVec3| (q - p).cross(s - p).dot(n) >= -1e-9;
                    (s - c).dot(n).abs() < 1e-9 && inside(c, a) && inside(a, b) && inside(b, c)
                })
                .unwrap_or_else(|| panic!("{s} lies on no lens triangle: {ray:?}"));
            let n = (a - c).cross(b - c).normalize();
            let d = (s - ray.points[k - 1].position).normalize();
            assert_near(
                "the thin-lens law",
                leaving(ray, k),
                ideal_lens(d, s, c, n, 0.5),
                1e-9,
            );
            crossings += 1;
        }
    }
    assert!(crossings >= 10, "{crossings} lens crossings");
}

/// scenes/clas.toml: two of Dr TIM's default CLAs (f₁ = f₂ = 0.1, periods 0.1, arrays at
/// z = 4.9 and 5.1, centred on x = ∓0.6), the left one without baffles. A line of sight from
/// the camera (slope t = x/4.9 across u) meets array 2 first, r from a lenslet centre, and
/// array 1 at 2ft − r from it: within the same telescope if |2ft − r| ≤ 0.05 (it then leaves
/// with its slope reversed, η = −1), in the neighbour's otherwise, which on the right means
/// the baffle at x = 0.65 between them (the sixth, from x = 0.15).
#[test]
fn clas_baffles_absorb_the_light_that_crosses_into_the_neighbouring_telescope() {
    let targets = [
        // r = 0.04, 2ft − r ≈ −0.014: stays.
        DVec3::new(0.64, 0.003, 4.9),
        // r = −0.04, 2ft − r ≈ 0.063: crosses x = 0.65.
        DVec3::new(0.56, 0.003, 4.9),
        // The same on the left, without baffles: crosses into the neighbour and goes on.
        DVec3::new(-0.56, 0.003, 4.9),
    ];
    let rays = trace_towards("clas", DVec3::ZERO, &targets);
    let names = |ray: &Traced| -> Vec<String> {
        ray.points.iter().filter_map(|p| p.object.clone()).collect()
    };
    let passes = &rays[0];
    let met = names(passes);
    assert_eq!(
        met[..2],
        ["CLAs/lenslet array 2", "CLAs/lenslet array 1"],
        "{met:?}"
    );
    // Leaves lenslet 1 with the slope reversed.
    let t = DVec3::new(0.64, 0.003, 0.0) / 4.9;
    let expected = (DVec3::new(-t.x, -t.y, 1.0)).normalize();
    assert_near("leaving the telescope", leaving(passes, 2), expected, 1e-9);
    let absorbed = &rays[1];
    assert_eq!(
        names(absorbed),
        ["CLAs/lenslet array 2", "CLAs/baffle u 6"],
        "{absorbed:?}"
    );
    assert_eq!(absorbed.end, "absorbed");
    assert!(
        (absorbed.last().x - 0.65).abs() < 1e-9,
        "{}",
        absorbed.last()
    );
    let stray = &rays[2];
    let met = names(stray);
    assert_eq!(
        met[..2],
        [
            "CLAs without baffles/lenslet array 2",
            "CLAs without baffles/lenslet array 1"
        ],
        "{met:?}"
    );
    // It meets array 1 in the neighbouring lenslet (centred on x = −0.7), beyond x = −0.65.
    assert!(stray.points[2].position.x < -0.65, "{stray:?}");
}

// ------------------------------------------------------------------------------------------
// Shapes
// ------------------------------------------------------------------------------------------

/// Möller–Trumbore: where the ray from `o` along `d` meets the triangle `t`, from either side.
fn triangle_hit(o: DVec3, d: DVec3, t: [DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-14 {
        return None;
    }
    let s = o - t[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let distance = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && distance > 1e-9).then_some(distance)
}

/// The nearest of the triangles `mesh` that the ray from `o` along the unit direction `d`
/// meets: its distance and index.
fn mesh_hit(o: DVec3, d: DVec3, mesh: &[[DVec3; 3]]) -> Option<(f64, usize)> {
    mesh.iter()
        .enumerate()
        .filter_map(|(k, &t)| triangle_hit(o, d, t).map(|distance| (distance, k)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The triangles of the binary little-endian PLY file `path` as timbre's generator writes it
/// (vertices of six doubles: position and normal; faces of a byte count and u32 indices),
/// each vertex mapped by `place`.
fn read_ply(path: &Path, place: impl Fn(DVec3) -> DVec3) -> Vec<[DVec3; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let end = b"end_header\n";
    let body = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    let header = std::str::from_utf8(&bytes[..body]).unwrap();
    let count = |element: &str| -> usize {
        header
            .lines()
            .find_map(|l| l.strip_prefix(&format!("element {element} ")))
            .unwrap()
            .parse()
            .unwrap()
    };
    let (vertices, faces) = (count("vertex"), count("face"));
    assert!(header.contains("property double nz\n") && header.contains("binary_little_endian"));
    let f64_at = |at: usize| f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
    let points: Vec<DVec3> = (0..vertices)
        .map(|k| {
            let at = body + 48 * k;
            place(DVec3::new(f64_at(at), f64_at(at + 8), f64_at(at + 16)))
        })
        .collect();
    let mut at = body + 48 * vertices;
    let mut triangles = Vec::new();
    for _ in 0..faces {
        assert_eq!(bytes[at], 3);
        let index = |k: usize| {
            u32::from_le_bytes(bytes[at + 1 + 4 * k..at + 5 + 4 * k].try_into().unwrap()) as usize
        };
        triangles.push([points[index(0)], points[index(1)], points[index(2)]]);
        at += 13;
    }
    assert_eq!(at, bytes.len());
    triangles
}

/// The triangles (fans of its polygons) of the OBJ file `path`, each vertex mapped by `place`.
fn read_obj(path: &Path, place: impl Fn(DVec3) -> DVec3) -> Vec<[DVec3; 3]> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut points = Vec::new();
    let mut triangles = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let v: Vec<f64> = words.map(|w| w.parse().unwrap()).collect();
                points.push(place(DVec3::from_slice(&v)));
            }
            Some("f") => {
                let corners: Vec<DVec3> = words
                    .map(|w| points[w.parse::<usize>().unwrap() - 1])
                    .collect();
                for k in 1..corners.len() - 1 {
                    triangles.push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    triangles
}

/// A ray from `o` along the unit direction `d` through the closed glass mesh `mesh` (index
/// ratio `n`, outward normals by the triangles' winding, `transmission` at each surface met),
/// by Snell's law and total internal reflection: where it leaves, its direction and the
/// fraction of light it carries; `None` if it misses or is trapped.
fn glass_mesh(
    o: DVec3,
    d: DVec3,
    mesh: &[[DVec3; 3]],
    n: f64,
    transmission: f64,
) -> Option<(DVec3, DVec3, f64)> {
    let normal = |t: [DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).normalize();
    let (t, k) = mesh_hit(o, d, mesh)?;
    let mut p = o + t * d;
    let mut inside = refract(d, normal(mesh[k]), 1.0 / n)?;
    let mut light = transmission;
    for _ in 0..20 {
        let (t, k) = mesh_hit(p, inside, mesh)?;
        p += t * inside;
        light *= transmission;
        let out = normal(mesh[k]);
        match refract(inside, -out, n) {
            Some(e) => return Some((p, e, light)),
            None => inside = inside - 2.0 * inside.dot(out) * out,
        }
    }
    None
}

/// scenes/mesh.toml: two meshes from files, placed by their transforms. Left, the bumpy
/// sphere of `meshes/bumpy-sphere.ply` scaled by 0.3 about (−0.45, −0.55, 6): every pixel
/// whose line of sight meets one of its triangles (read from the file here) sees it at that
/// distance. Right, the glass prism of `meshes/prism.obj` (n = 1.5, transmission 0.96),
/// scaled by (0.4, 0.4, 0.7), turned 90° about y (its axis along x, apex up) and moved to
/// (0.45, −0.6, 6): every pixel of it shows what its line of sight, refracted through it by
/// Snell's law, meets — among it the floor, deflected down towards the prism's base.
#[test]
fn mesh_scene_shows_the_bumpy_sphere_and_the_glass_prism() {
    let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/meshes");
    let bumpy = read_ply(&meshes.join("bumpy-sphere.ply"), |v| {
        0.3 * v + DVec3::new(-0.45, -0.55, 6.0)
    });
    let prism = read_obj(&meshes.join("prism.obj"), |v| {
        let s = DVec3::new(0.4 * v.x, 0.4 * v.y, 0.7 * v.z);
        DVec3::new(s.z, s.y, -s.x) + DVec3::new(0.45, -0.6, 6.0)
    });
    assert_eq!(prism.len(), 8);
    let bumpy_centre = DVec3::new(-0.45, -0.55, 6.0);
    let bumpy_radius = bumpy
        .iter()
        .flatten()
        .map(|v| (*v - bumpy_centre).length())
        .fold(0.0, f64::max);
    let camera = Camera::standard(20.0, 160, 120);
    let picture = render("mesh", 160, 120);
    // The bumpy sphere's triangles by the pixels they may cover (their projections' boxes,
    // widened by a pixel), so that each line of sight is tested against a few.
    let mut cover = vec![Vec::new(); 160 * 120];
    for t in &bumpy {
        let corners = t.map(|v| camera.pixel(v));
        let (x0, x1) = corners
            .iter()
            .fold((f64::INFINITY, -f64::INFINITY), |a, c| {
                (a.0.min(c.0), a.1.max(c.0))
            });
        let (y0, y1) = corners
            .iter()
            .fold((f64::INFINITY, -f64::INFINITY), |a, c| {
                (a.0.min(c.1), a.1.max(c.1))
            });
        for y in (y0 - 1.0).floor().max(0.0) as usize..=((y1 + 1.0).ceil() as usize).min(119) {
            for x in (x0 - 1.0).floor().max(0.0) as usize..=((x1 + 1.0).ceil() as usize).min(159) {
                cover[y * 160 + x].push(*t);
            }
        }
    }
    let mut sphere_pixels = 0;
    let seen = assert_view(&picture, Lattice::Standard, |x, y| {
        let d = camera.direction(x as f64, y as f64).normalize();
        if sphere_hit(DVec3::ZERO, d, bumpy_centre, bumpy_radius).is_some() {
            // Clear of the outline: the neighbouring lines of sight agree.
            let near = &cover[y * 160 + x];
            let hits =
                [(0.0, 0.0), (0.3, 0.0), (-0.3, 0.0), (0.0, 0.3), (0.0, -0.3)].map(|(dx, dy)| {
                    mesh_hit(
                        DVec3::ZERO,
                        camera.direction(x as f64 + dx, y as f64 + dy).normalize(),
                        near,
                    )
                });
            if let Some((t, _)) = hits[0] {
                if hits.iter().all(Option::is_some) {
                    assert_eq!(picture.object(x, y), "bumpy sphere", "pixel ({x}, {y})");
                    let depth = picture.depth(x, y);
                    assert!(
                        (depth / t - 1.0).abs() < 1e-6,
                        "pixel ({x}, {y}): depth {depth}, not {t}"
                    );
                    sphere_pixels += 1;
                }
            } else if hits.iter().all(Option::is_none) {
                assert_ne!(picture.object(x, y), "bumpy sphere", "pixel ({x}, {y})");
            }
            return None;
        }
        let edges = [(0.3, 0.0), (-0.3, 0.0), (0.0, 0.3), (0.0, -0.3)].map(|(dx, dy)| {
            mesh_hit(
                DVec3::ZERO,
                camera.direction(x as f64 + dx, y as f64 + dy).normalize(),
                &prism,
            )
            .map(|h| h.1)
        });
        let hit = mesh_hit(DVec3::ZERO, d, &prism);
        if edges
            .iter()
            .any(|e| e.map(|k| k / 2) != hit.map(|h| h.1 / 2))
        {
            return None; // near an edge of a face
        }
        hit?;
        assert_eq!(picture.object(x, y), "prism", "pixel ({x}, {y})");
        let (exit, out, light) = glass_mesh(DVec3::ZERO, d, &prism, 1.5, 0.96)?;
        // Not back towards the bumpy sphere.
        (sphere_hit(exit, out, bumpy_centre, bumpy_radius + 0.01).is_none())
            .then_some((exit, out, light))
    });
    let counts = tally(&seen);
    assert!(
        sphere_pixels > 1000 && counts.get("floor").copied().unwrap_or(0) > 500,
        "{sphere_pixels} pixels of the bumpy sphere; through the prism {counts:?}"
    );
}

/// Traces lines of sight from `eye` towards each point `p` of `cases`, which the scene file's
/// numbers put on the surface of the object `name` facing `eye` (asserted here, by the
/// surface's outward `normal` there): each must meet that object first, at that point.
/// Returns the traced rays.
#[track_caller]
fn assert_first_hits(scene_name: &str, eye: DVec3, cases: &[(&str, DVec3, DVec3)]) -> Vec<Traced> {
    let targets: Vec<DVec3> = cases.iter().map(|c| c.1).collect();
    let rays = trace_towards(scene_name, eye, &targets);
    for (ray, &(name, p, normal)) in rays.iter().zip(cases) {
        assert!(normal.dot(p - eye) < 0.0, "{p} faces away from the camera");
        assert_eq!(
            ray.points[1].object.as_deref(),
            Some(name),
            "the line of sight to {p}: {ray:?}"
        );
        assert_near(name, ray.points[1].position, p, 1e-9);
    }
    rays
}

/// The unit vector along the part of `v` perpendicular to the unit vector `axis`.
fn perpendicular(v: DVec3, axis: DVec3) -> DVec3 {
    (v - v.dot(axis) * axis).normalize()
}

/// scenes/shapes.toml: one object of each basic shape in the empty studio, each where the
/// file's numbers put it: lines of sight to points of their surfaces facing the camera meet
/// them there first. The fence (the plane z = 14, u along x, v along −y, tiles 0.5 wide) is a
/// chequerboard of wood (where ⌊u/w⌋ + ⌊v/w⌋ is even) and holes; the chequered disc's tiles
/// (0.25 wide, u along x and v along −y from its centre) are black and yellow the same way.
#[test]
fn shapes_scene_places_each_shape() {
    let name = "shapes";
    let eye = DVec3::ZERO;
    let ball = DVec3::new(-1.0, -0.5, 10.0);
    let towards = -ball.normalize();
    let post = DVec3::new(1.0, -0.55, 10.0);
    let post_side = -DVec3::new(1.0, 0.0, 10.0).normalize();
    let (u, v) = (DVec3::new(0.7, 0.2, 0.0), DVec3::new(0.1, 0.6, 0.2));
    let apex = DVec3::new(0.0, -0.2, 9.5);
    let (front_left, front_right) = (DVec3::new(-0.4, -1.0, 9.1), DVec3::new(0.4, -1.0, 9.1));
    let front = (front_left + apex + front_right) / 3.0;
    let rays = assert_first_hits(
        name,
        eye,
        &[
            ("mirror ball", ball + 0.5 * towards, towards),
            ("post", post + 0.3 * post_side, post_side),
            ("post", DVec3::new(1.1, -0.1, 9.85), DVec3::Y),
            ("chequered disc", DVec3::new(0.1, 0.6, 11.0), -DVec3::Z),
            (
                "tile",
                DVec3::new(-1.5, 0.3, 11.0) + 0.5 * (u + v),
                -u.cross(v),
            ),
            // Triangle [0, 4, 1], wound counter-clockwise seen from outside.
            (
                "pyramid",
                front,
                (apex - front_left).cross(front_right - front_left),
            ),
            // The fence: a wooden tile (u, v) = (0.25, 0.25) and a hole (0.75, 0.25).
            ("fence", DVec3::new(0.25, -0.25, 14.0), -DVec3::Z),
            ("fence", DVec3::new(0.75, -0.25, 14.0), -DVec3::Z),
        ],
    );
    assert_eq!(rays[6].last_object(), "fence");
    assert!(
        ["floor", "sky"].contains(&rays[7].last_object()),
        "{:?}",
        rays[7]
    );

    let camera = Camera::standard(20.0, 320, 240);
    let picture = render(name, 320, 240);
    let centre = DVec3::new(0.0, 0.55, 11.0);
    let w = 0.25;
    for i in -2i32..2 {
        for j in -2i32..2 {
            let (tu, tv) = ((i as f64 + 0.5) * w, (j as f64 + 0.5) * w);
            if tu.hypot(tv) > 0.5 - 0.3 * w {
                continue;
            }
            let (x, y) = camera.pixel_of(centre + DVec3::new(tu, -tv, 0.0));
            let c = picture.rgb(x, y);
            assert_eq!(picture.object(x, y), "chequered disc");
            if (i + j).rem_euclid(2) == 0 {
                assert!(is_grey(c), "tile ({i}, {j}) is {c}, not black");
            } else {
                assert!(
                    c.z == 0.0 && c.x > c.y && c.y > 0.0,
                    "tile ({i}, {j}) is {c}, not yellow"
                );
            }
        }
    }
}

/// scenes/curved-shapes.toml: the curved shapes in the empty studio, each where the file's
/// numbers put it: lines of sight to points of their surfaces facing the camera (worked out
/// from each shape's apex, centre, axis, radii and angles) meet them there first — the cone's
/// side halfway down (radius 0.5 tan 22°), the ellipsoid's front and a point off its axes, the
/// tube's annular end and outer wall, the inside of the mirror dish at its vertex, the inside
/// of the spherical cap at its pole, the elliptic rod's end and the open pipe's wall.
#[test]
fn curved_shapes_scene_places_each_shape() {
    let eye = DVec3::ZERO;
    let mut cases = Vec::new();
    // Cone: apex, axis into the cone, half-angle; the side s = 0.5 down the axis.
    let (apex, axis, half) = (
        DVec3::new(-1.35, -0.05, 10.0),
        DVec3::NEG_Y,
        22f64.to_radians(),
    );
    let q = apex + 0.5 * axis;
    let p = perpendicular(eye - q, axis);
    cases.push((
        "cone",
        q + 0.5 * half.tan() * p,
        half.cos() * p - half.sin() * axis,
    ));
    // Ellipsoid: its front, and the point (0.5, 0.3, −√0.66) of the unit sphere stretched.
    let (c, semi) = (DVec3::new(-0.55, -0.75, 9.5), DVec3::new(0.4, 0.25, 0.3));
    cases.push(("ellipsoid", c - semi.z * DVec3::Z, DVec3::NEG_Z));
    let unit = DVec3::new(0.5, 0.3, -(1.0f64 - 0.25 - 0.09).sqrt());
    cases.push(("ellipsoid", c + unit * semi, unit / semi));
    // Tube: its upper end's annulus and its outer wall halfway.
    let (start, end) = (DVec3::new(0.35, -1.0, 9.9), DVec3::new(0.35, -0.45, 9.55));
    let axis = (end - start).normalize();
    cases.push(("tube", end + 0.24 * perpendicular(DVec3::X, axis), axis));
    let mid = 0.5 * (start + end);
    let side = perpendicular(eye - mid, axis);
    cases.push(("tube", mid + 0.3 * side, side));
    // The dish: the vertex, seen from inside the bowl (its axis points into the bowl).
    let axis = DVec3::new(-0.4, 0.1, -1.0).normalize();
    cases.push(("dish", DVec3::new(1.3, -0.45, 10.3), axis));
    // The cap: its pole, seen from inside.
    let (centre, pole) = (DVec3::new(-1.1, 0.45, 11.5), DVec3::new(-1.1, 0.05, 11.8));
    cases.push(("cap", pole, (centre - pole).normalize()));
    // The elliptic rod: the centre of its near end.
    let (start, end) = (DVec3::new(-0.15, 0.35, 11.0), DVec3::new(0.45, 0.45, 12.5));
    cases.push(("elliptic cylinder", start, (start - end).normalize()));
    // The pipe: its outer wall halfway.
    let (start, end) = (DVec3::new(0.85, 0.15, 11.0), DVec3::new(1.5, 0.55, 12.0));
    let (mid, axis) = (0.5 * (start + end), (end - start).normalize());
    let side = perpendicular(eye - mid, axis);
    cases.push(("pipe", mid + 0.22 * side, side));
    assert_first_hits("curved-shapes", eye, &cases);
}

/// The far intersection of the line from `o` along the unit direction `d` with a sphere: where
/// a line of sight leaves it (the inside of a sphere cut out of a solid).
fn sphere_exit(o: DVec3, d: DVec3, c: DVec3, r: f64) -> Option<f64> {
    let oc = o - c;
    let b = oc.dot(d);
    let disc = b * b - (oc.length_squared() - r * r);
    (disc >= 0.0).then(|| -b + disc.sqrt())
}

/// scenes/csg.toml: constructive solid geometry, each solid where and as the file's numbers
/// make it (camera at (0, 0.6, 0), looking along (0, −0.08, 1)). Lines of sight meet the
/// dumbbell's rod between its balls; the drilled ball's flat top (the half-space above
/// y = −0.3 cut away) at y = −0.3, facing up; the post's bite (an inverted ball) on the far
/// side of that ball, inside the post; the sheared ball (x += 0.6 y) where the shear takes
/// the points of its sphere; the pane where it has no hole. Lines of sight through the
/// drilled hole and through a hole of the pane pass through them.
#[test]
fn csg_scene_shows_unions_differences_and_bites() {
    let name = "csg";
    let eye = DVec3::new(0.0, 0.6, 0.0);
    let mut cases = Vec::new();
    // The dumbbell's rod, radius 0.12 along x at y = −0.55, z = 12, between x = −2.25 and −1.95.
    let rod = DVec3::new(-2.1, -0.55, 12.0);
    let side = perpendicular(eye - rod, DVec3::X);
    cases.push(("union", rod + 0.12 * side, side));
    // The drilled ball's cut top, 0.3 from its axis beside the hole.
    cases.push(("difference", DVec3::new(-0.2, -0.3, 12.0), DVec3::Y));
    // The bite: where the line of sight to the post's front at y = −0.5 leaves the ball
    // (0.45, −0.5, 11.75), r = 0.25, inside the post (axis x = 0.7, z = 12, r = 0.3).
    let post = DVec3::new(0.7, -0.5, 12.0);
    let front = post + 0.3 * perpendicular(eye - post, DVec3::Y);
    let bite = DVec3::new(0.45, -0.5, 11.75);
    let d = (front - eye).normalize();
    let hit = eye + sphere_exit(eye, d, bite, 0.25).unwrap() * d;
    assert!(
        (hit - post).truncate().length() < 0.3
            || DVec3::new(hit.x - 0.7, 0.0, hit.z - 12.0).length() < 0.3
    );
    cases.push(("inverse", hit, bite - hit));
    // The sheared ball: the points 0.4 (0, 0, −1) and 0.4 (0, 0.6, −0.8) of its sphere under
    // x += 0.6 y, moved to (2.1, −0.6, 12); normals by the inverse transpose.
    let shear = |p: DVec3| DVec3::new(p.x + 0.6 * p.y, p.y, p.z) + DVec3::new(2.1, -0.6, 12.0);
    let normal = |p: DVec3| DVec3::new(p.x, p.y - 0.6 * p.x, p.z);
    for p in [DVec3::new(0.0, 0.0, -0.4), DVec3::new(0.0, 0.24, -0.32)] {
        cases.push(("sheared ball", shear(p), normal(p)));
    }
    // The pane (z = 17), between its holes (round (±2, −0.4) and (0, −0.4), radius 0.35).
    cases.push((
        "pane with holes",
        DVec3::new(-1.0, -0.4, 17.0),
        DVec3::NEG_Z,
    ));
    assert_first_hits(name, eye, &cases);
    // Through the drilled hole (along z through (−0.5, −0.5), radius 0.2) and a hole of the pane.
    let through = trace_towards(
        name,
        eye,
        &[DVec3::new(-0.5, -0.5, 11.5), DVec3::new(0.0, -0.4, 17.0)],
    );
    // (The first line of sight crosses the ball's sphere below the cut, inside the hole.)
    let d = (DVec3::new(-0.5, -0.5, 11.5) - eye).normalize();
    let (ball, r) = (DVec3::new(-0.5, -0.5, 12.0), 0.5);
    let (t0, t1) = (
        sphere_hit(eye, d, ball, r).unwrap(),
        sphere_exit(eye, d, ball, r).unwrap(),
    );
    for t in [t0, t1] {
        let p = eye + t * d;
        assert!(
            p.y < -0.3 && DVec3::new(p.x + 0.5, p.y + 0.5, 0.0).length() < 0.2,
            "{p}"
        );
    }
    assert_eq!(
        through[0].points[1].object.as_deref(),
        Some("floor"),
        "{:?}",
        through[0]
    );
    assert_eq!(
        through[1].points[1].object.as_deref(),
        Some("floor"),
        "{:?}",
        through[1]
    );
    // The cut top is flat: every pixel whose line of sight meets the plane y = −0.3 well
    // inside the ball's section (radius √(0.5² − 0.2²)) sees it facing up.
    let camera = Camera::new(eye, DVec3::new(0.0, -0.08, 1.0), DVec3::Y, 40.0, 640, 480);
    let picture = render(name, 640, 480);
    let mut flat = 0;
    for (x, y) in picture.pixels() {
        let d = camera.direction(x as f64, y as f64).normalize();
        let p = eye + ((-0.3 - eye.y) / d.y) * d;
        if d.y < 0.0 && DVec3::new(p.x + 0.5, 0.0, p.z - 12.0).length() < 0.4 {
            assert_eq!(picture.object(x, y), "difference", "pixel ({x}, {y})");
            assert_near("the cut's normal", picture.normal(x, y), DVec3::Y, 1e-6);
            flat += 1;
        }
    }
    assert!(flat > 50, "{flat} pixels see the cut");
}

/// scenes/polyhedra.toml: the polyhedra, each where the file's numbers put it: lines of sight
/// meet the cuboid (turned 30° about y, right-handed) on its front, right and top faces at
/// their centres; the wedge (apex edge along z, bisector down, 40°) on its right face and its
/// front end; the parallelepiped on its front face; the glass prism on its end; the hexagon at
/// its centre; the twisted bilinear patch at its middle; the cube on its front face away from
/// the ball cut from its corner, and inside that ball's surface where it is cut; and the
/// Platonic solids within their circumradii.
#[test]
fn polyhedra_scene_places_each_solid() {
    let name = "polyhedra";
    let eye = DVec3::ZERO;
    let turn = |v: DVec3| {
        let (s, c) = 30f64.to_radians().sin_cos();
        DVec3::new(c * v.x + s * v.z, v.y, -s * v.x + c * v.z)
    };
    let cuboid = DVec3::new(-1.3, -0.8, 10.0);
    let mut cases = vec![
        (
            "cuboid",
            cuboid + turn(DVec3::new(0.0, 0.0, -0.2)),
            turn(DVec3::NEG_Z),
        ),
        (
            "cuboid",
            cuboid + turn(DVec3::new(0.25, 0.0, 0.0)),
            turn(DVec3::X),
        ),
        ("cuboid", cuboid + DVec3::new(0.0, 0.2, 0.0), DVec3::Y),
    ];
    // The wedge: legs at ±20° from the bisector (−y) about the apex edge along z.
    let (apex, half) = (DVec3::new(-0.6, -0.55, 10.0), 20f64.to_radians());
    let leg = DVec3::new(half.sin(), -half.cos(), 0.0);
    cases.push((
        "wedge",
        apex + 0.2 * leg,
        DVec3::new(half.cos(), half.sin(), 0.0),
    ));
    cases.push(("wedge", apex + DVec3::new(0.0, -0.2, -0.25), DVec3::NEG_Z));
    // The parallelepiped's face spanned by its first two edges, on the camera's side.
    let (centre, e1, e2, e3) = (
        DVec3::new(0.1, -0.8, 10.0),
        DVec3::new(0.5, 0.0, 0.0),
        DVec3::new(0.2, 0.4, 0.0),
        DVec3::new(0.15, 0.0, 0.4),
    );
    let _ = (e1, e2);
    cases.push(("parallelepiped", centre - 0.5 * e3, DVec3::NEG_Z));
    // The triangular prism's end at x = 0.7, at its triangle's centroid.
    cases.push((
        "triangular prism",
        DVec3::new(0.7, -0.85, 9.85),
        DVec3::NEG_X,
    ));
    // The hexagon's centre.
    cases.push(("convex polygon", DVec3::new(1.3, 0.75, 11.0), DVec3::NEG_Z));
    // The bilinear patch's middle, the mean of its corners (either side of it is a surface).
    let corners = [
        DVec3::new(-1.4, -0.45, 11.0),
        DVec3::new(-0.5, -0.45, 11.8),
        DVec3::new(-0.5, 0.35, 11.0),
        DVec3::new(-1.4, 0.35, 11.8),
    ];
    let middle = corners.iter().sum::<DVec3>() / 4.0;
    let (du, dv) = (
        0.5 * (corners[1] - corners[0] + corners[2] - corners[3]),
        0.5 * (corners[3] - corners[0] + corners[2] - corners[1]),
    );
    let n = du.cross(dv);
    cases.push((
        "bilinear surface",
        middle,
        if n.dot(middle) < 0.0 { n } else { -n },
    ));
    // The cube (0.6 wide about (0.8, −0.05, 11)) away from, and inside, the ball cut out of it.
    cases.push((
        "cube minus ball",
        DVec3::new(0.95, -0.2, 10.7),
        DVec3::NEG_Z,
    ));
    let (ball, r) = (DVec3::new(0.6, 0.15, 10.7), 0.35);
    let d = (ball - eye).normalize();
    let bitten = eye + sphere_exit(eye, d, ball, r).unwrap() * d;
    assert!((bitten - DVec3::new(0.8, -0.05, 11.0)).abs().max_element() < 0.3);
    cases.push(("cube minus ball", bitten, ball - bitten));
    assert_first_hits(name, eye, &cases);
    for (solid, centre, radius) in [
        ("icosahedron", DVec3::new(-1.3, 0.75, 11.0), 0.3),
        ("dodecahedron", DVec3::new(-0.45, 0.75, 11.0), 0.3),
        ("tetrahedron", DVec3::new(0.4, 0.7, 11.0), 0.4),
    ] {
        let ray = &trace_towards(name, eye, &[centre])[0];
        assert_eq!(ray.points[1].object.as_deref(), Some(solid), "{ray:?}");
        let off = (ray.points[1].position - centre).length();
        assert!(off <= radius + 1e-9 && off > 0.0, "{solid}: {off}");
    }
}

/// scenes/visual-aids.toml: Dr TIM's visual aids, each where the file's numbers put it (camera
/// at (0, 0.5, 0) looking along (0, −0.05, 1)): lines of sight meet Tim's head, the
/// coordinate system's x and y arrows halfway along (from (−3, −0.9, 12), 1 long), the arrow's
/// shaft halfway, the ruler between two ticks; and the ball's surface-coordinate axes at
/// (u, v) = (−1.6, 0.8), i.e. longitude u/r and polar angle v/r on the ball of radius 0.6 at
/// (−1.8, 0.9, 13): the blue arrow along the outward normal, the red along û (increasing
/// longitude) and the green along v̂ = n̂ × û, each 0.6 long.
#[test]
fn visual_aids_stand_where_the_file_puts_them() {
    let name = "visual-aids";
    let eye = DVec3::new(0.0, 0.5, 0.0);
    let (ball, r): (DVec3, f64) = (DVec3::new(-1.8, 0.9, 13.0), 0.6);
    let (phi, theta) = (-1.6 / r, 0.8 / r);
    let n = DVec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        theta.sin() * phi.cos(),
    );
    let foot = ball + r * n;
    let u = DVec3::new(phi.cos(), 0.0, -phi.sin());
    let v = n.cross(u);
    let targets = [
        DVec3::new(0.0, 0.3, 12.0),
        DVec3::new(-2.5, -0.9, 12.0),
        DVec3::new(-3.0, -0.4, 12.0),
        DVec3::new(2.2, -0.2, 11.25),
        DVec3::new(0.05, -0.98, 8.0),
        foot + 0.3 * n,
        foot + 0.3 * u,
        foot + 0.3 * v,
    ];
    let rays = trace_towards(name, eye, &targets);
    let first: Vec<&str> = rays
        .iter()
        .map(|r| r.points[1].object.as_deref().unwrap_or("nothing"))
        .collect();
    assert!(first[0].starts_with("Tim/"), "{first:?}");
    assert_eq!(
        &first[1..],
        [
            "axes/x axis",
            "axes/y axis",
            "arrow",
            "ruler",
            "ball/normal",
            "ball/u axis",
            "ball/v axis"
        ],
        "{rays:?}"
    );
}

/// scenes/research/ThreeSkewLenses.toml (Dr TIM's ThreeSkewLenses with lens holograms that
/// image the eye): lens k images the eye's image by lens k − 1 into its image by an ideal thin
/// lens of focal length f_k, worked out here by Gauss's lens equation: for an object at axial
/// distance a from the principal point P along the normal n̂ (negative in front), the image is
/// at a′ with 1/a′ = 1/a + 1/f, magnified a′/a about P. A line of sight from the eye
/// (0, 0, −10) that meets lens 1 first (the left of the view, where lens 1 lies nearest the
/// eye) leaves it along the line through E1, towards it (real); if it meets lens 2 next, it
/// leaves that along the line through E2, and if then lens 3, along the line through E3, away
/// from both (virtual).
#[test]
fn the_three_skew_lens_holograms_image_the_eye_as_ideal_lenses() {
    let name = "research/ThreeSkewLenses";
    let eye = DVec3::new(0.0, 0.0, -10.0);
    let deg = |a: f64| a.to_radians();
    let lenses = [
        (
            DVec3::new(-0.5, -0.5, 0.0),
            DVec3::new(deg(-40.0).sin(), 0.0, deg(-40.0).cos()),
            1.0,
        ),
        (
            DVec3::new(0.0, -0.5, 0.0),
            DVec3::new(deg(-20.0).sin(), 0.0, deg(-20.0).cos()),
            -0.3,
        ),
        (
            DVec3::new(0.5, -0.5, 0.0),
            DVec3::new(0.0, deg(30.0).sin(), deg(30.0).cos()),
            1.0,
        ),
    ];
    let mut images = Vec::new();
    let mut object = eye;
    for &(p, n, f) in &lenses {
        let a = (object - p).dot(n);
        let a_image = 1.0 / (1.0 / a + 1.0 / f);
        object = p + (a_image / a) * (object - p);
        images.push(object);
    }
    // A grid over the left of the view, and the narrow band from (−1.4, 0.4) to (−0.95, −0.1)
    // (at z = 0) whose lines of sight go on through lens 3.
    let band = [
        (-1.4, 0.4),
        (-1.31, 0.3),
        (-1.22, 0.2),
        (-1.13, 0.1),
        (-1.13, 0.2),
        (-1.04, 0.0),
        (-1.04, 0.1),
        (-0.95, -0.1),
        (-0.95, 0.0),
    ];
    let targets: Vec<DVec3> = (0..48)
        .map(|k| {
            DVec3::new(
                -1.75 + 0.1 * (k % 8) as f64,
                -1.25 + 0.5 * (k / 8) as f64,
                0.0,
            )
        })
        .chain(band.map(|(x, y)| DVec3::new(x, y, 0.0)))
        .collect();
    let rays = trace_towards(name, eye, &targets);
    let mut met = [0; 3];
    for ray in &rays {
        for k in 0..3 {
            let (Some(hit), Some(next)) = (ray.points.get(k + 1), ray.points.get(k + 2)) else {
                break;
            };
            if hit.object.as_deref() != Some(&format!("lens {}", k + 1)) {
                break;
            }
            met[k] += 1;
            let e = (next.position - hit.position).normalize();
            let along = (images[k] - hit.position).dot(e);
            let miss = (images[k] - hit.position - along * e).length();
            assert!(
                miss < 1e-9,
                "lens {}: misses E{} by {miss}: {ray:?}",
                k + 1,
                k + 1
            );
            assert_eq!(along > 0.0, k == 0, "lens {}: {along}", k + 1);
        }
    }
    assert!(
        met[0] >= 40 && met[1] >= 40 && met[2] >= 8,
        "lines of sight in order: {met:?}"
    );
}

/// scenes/research/HolographicLensStarConicSectionTrajectoryPlotter.toml, Dr TIM's research
/// program of that name with its lens-hologram option: 32 lenses round the y axis through the
/// origin, each of focal length f = 0.5/sin(π/32), made as Dr TIM's `PhaseHologramOfLens`. At
/// each lens a trajectory's unit direction d keeps its side of the lens and has its tangential
/// part changed by −(S − P)ₜ/f, S where it meets the lens and P = 0 the principal point (the
/// lens plane contains the y axis, so (S − P)ₜ = S); where that makes the tangential part
/// longer than 1 the wave is evanescent and the ray is reflected in the lens instead (Dr TIM's
/// `PhaseHologram`). Both of the program's trajectories, from (0, 0, 1) and (0, 0, 1.5) along
/// θ = 225.1° in the (z, x) plane, do so at every lens they meet, in the plane y = 0, until
/// the 128 interactions the program allows are spent; some of them are reflected (which
/// ideal lenses never do).
#[test]
fn research_holographic_lens_star_bends_rays_as_lens_holograms() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/research/HolographicLensStarConicSectionTrajectoryPlotter.toml");
    let f = 0.5 / (PI / 32.0).sin();
    let rays = trace_file_with(&path, &[]);
    assert_eq!(rays.len(), 2);
    let mut reflected = 0;
    for (ray, z0) in rays.iter().zip([1.0, 1.5]) {
        assert_near(
            "start",
            ray.points[0].position,
            DVec3::new(0.0, 0.0, z0),
            1e-12,
        );
        assert_eq!(ray.end, "max-interactions");
        assert_eq!(ray.points.len(), 129);
        for k in 1..ray.points.len() - 1 {
            let s = ray.points[k].position;
            assert!(s.y.abs() < 1e-9, "left the plane y = 0 at {s}");
            let lens = ray.points[k].object.as_deref().unwrap();
            assert!(lens.starts_with("lens star/lens "), "{lens}");
            // The lens's normal: horizontal, perpendicular to S.
            let n = DVec3::new(-s.z, 0.0, s.x).normalize();
            let d = leaving(ray, k - 1);
            let tangential = d - d.dot(n) * n - s / f;
            let normal2 = 1.0 - tangential.length_squared();
            let expected = if normal2 > 0.0 {
                tangential + d.dot(n).signum() * normal2.sqrt() * n
            } else {
                reflected += 1;
                d - 2.0 * d.dot(n) * n
            };
            assert_near(
                "the direction after a lens",
                leaving(ray, k),
                expected,
                1e-9,
            );
        }
    }
    assert!(reflected > 0);
}

/// scenes/appearance.toml: against the sky (0.5, 0.5, 1), the pixel nearest each object's
/// centre shows Beer–Lambert's exp(−a d) through the tinted cube (a = (0.2, 1.5, 4), d the
/// length of its line of sight between the cube's front and back faces z = 7.75 and 8.25), the
/// filter's channels (0.2, 1, 0.3) of the sky, and through the semi-transparent ball's two
/// surfaces 0.4 red + 0.6 (0.4 red + 0.6 sky).
#[test]
fn appearance_shows_tint_filter_and_semi_transparency() {
    let (w, h) = (160, 120);
    let camera = Camera::standard(20.0, w, h);
    let picture = render("appearance", w, h);
    let sky = DVec3::new(0.5, 0.5, 1.0);
    let expect = |centre: DVec3, name: &str, colour: &dyn Fn(DVec3) -> DVec3| {
        let (x, y) = camera.pixel_of(centre);
        assert_eq!(picture.object(x, y), name);
        let d = camera.direction(x as f64, y as f64).normalize();
        let expected = colour(d);
        let got = picture.rgb(x, y);
        assert!(
            (got - expected).abs().max_element() < 1e-6,
            "{name}: got {got}, expected {expected}"
        );
    };
    let a = DVec3::new(0.2, 1.5, 4.0);
    expect(DVec3::new(-0.9, 0.2, 8.0), "tinted cube", &|d| {
        let length = 0.5 / d.z;
        sky * DVec3::new(
            (-a.x * length).exp(),
            (-a.y * length).exp(),
            (-a.z * length).exp(),
        )
    });
    expect(DVec3::new(0.0, 0.2, 8.0), "green filter", &|_| {
        sky * DVec3::new(0.2, 1.0, 0.3)
    });
    let red = DVec3::new(1.0, 0.1, 0.1);
    expect(DVec3::new(0.9, 0.2, 8.0), "semi-transparent ball", &|_| {
        0.4 * red + 0.6 * (0.4 * red + 0.6 * sky)
    });
}

/// scenes/research/LensStarTrajectoryPlotter.toml: the ray from (−0.5, 0, 10) along +z first
/// meets lens 4 (at −216° from +x about the axis through (0, 0, 10)) at z = 10 + 0.5 tan 36°,
/// then lens 5, and leaves for the sky; it stays in the plane y = 0, and at each lens its
/// direction turns
/// by the ideal thin lens's law (f = 1, principal point on the axis): the tangential part of
/// the direction per unit of its normal part loses s / f, s the point's offset from the axis.
/// The picture shows the semi-transparent edges: the edge objects' light is a quarter shiny
/// red and three quarters what lies behind them.
#[test]
fn research_lens_star_trajectory_turns_by_the_thin_lens_law() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/research/LensStarTrajectoryPlotter.toml");
    let rays = trace_file(&path);
    assert_eq!(rays.len(), 1);
    let ray = &rays[0];
    let axis = DVec3::new(0.0, 0.0, 10.0);
    assert_near(
        "start",
        ray.points[0].position,
        DVec3::new(-0.5, 0.0, 10.0),
        1e-12,
    );
    assert_eq!(
        ray.points[1].object.as_deref(),
        Some("star of lenses/lens 4")
    );
    let first = DVec3::new(-0.5, 0.0, 10.0 + 0.5 * 36f64.to_radians().tan());
    assert_near("first lens", ray.points[1].position, first, 1e-9);
    // Lenses 4 and 5, then out to the sky.
    assert_eq!(ray.points.len(), 4, "{ray:?}");
    assert_eq!(ray.points[3].object.as_deref(), Some("sky"));
    for k in 1..ray.points.len() - 1 {
        let p = ray.points[k].position;
        assert!(p.y.abs() < 1e-9, "left the plane y = 0 at {p}");
        let lens = ray.points[k].object.as_deref().unwrap();
        assert!(lens.starts_with("star of lenses/lens "), "{lens}");
        let s = p - axis;
        let n = DVec3::new(-s.z, 0.0, s.x).normalize();
        let d = leaving(ray, k - 1);
        let dn = d.dot(n);
        let tangential = (d - dn * n) / dn.abs() - s;
        let expected = (tangential + dn.signum() * n).normalize();
        assert_near("after the lens", leaving(ray, k), expected, 1e-9);
    }

    let d =
        timbre::scene::file::parse(&std::fs::read_to_string(&path).unwrap(), "ls.toml").unwrap();
    let edge = d
        .objects
        .iter()
        .find(|o| o.name == "star of lenses/axial edge")
        .expect("the axial edge");
    let timbre::surfaces::Surface::SemiTransparent(mix) = &edge.surface else {
        panic!("{:?}", edge.surface)
    };
    let red = timbre::surfaces::Surface::Coloured(timbre::surfaces::Coloured {
        diffuse: DVec3::X,
        specular: DVec3::ONE,
    });
    assert_eq!(mix.parts[0].surface, red);
    assert_eq!(
        (mix.parts[0].weight, mix.parts[1].weight),
        (DVec3::splat(0.25), DVec3::splat(0.75))
    );
}

/// The example picture `scenes/pictures/NAME`.
fn example_picture(name: &str) -> image::RgbImage {
    common::cli::decode_png(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes/pictures")
            .join(name),
    )
}

/// The texel of `png` (8-bit, read as value / 255) at picture coordinates u (across, repeated)
/// and v (down from the top); `None` within `margin` texels of a texel's edge, where rounding
/// (or an approximation) decides.
fn texel_of(png: &image::RgbImage, u: f64, v_down: f64, margin: f64) -> Option<DVec3> {
    let (w, h) = (png.width() as f64, png.height() as f64);
    let (x, y) = ((u - u.floor()) * w, v_down * h);
    let edge = |t: f64| (t - t.round()).abs() < margin;
    if edge(x) || edge(y) || !(0.0..h).contains(&y) {
        return None;
    }
    let p = png.get_pixel(x as u32 % png.width(), y as u32);
    Some(DVec3::from_array(p.0.map(|c| (c as f32 / 255.0) as f64)))
}

/// scenes/image-sky.toml: every pixel that sees the sky shows the texel of the
/// equirectangular picture in its direction d, worked out here: u = 1/2 + atan2(dx, dz)/2π
/// (the centre ahead along +z, +x at 3/4, so that it reads unmirrored), rows from the top
/// 1/2 − elevation/π. On the mirror ball (radius 1 at (0, 0, 8)) the pixels whose reflected
/// direction d − 2(d·n)n rises show 0.9 of the texel in that direction (the floor is below).
/// The label "+Z" (white) is ahead, so some sky pixels near the centre are white.
#[test]
fn image_sky_shows_the_texel_in_each_direction() {
    let (w, h) = (160, 90);
    let camera = Camera::new(DVec3::ZERO, DVec3::Z, DVec3::Y, 100.0, w, h);
    let picture = render("image-sky", w, h);
    let png = example_picture("sky.png");
    let sky = |d: DVec3| {
        let elevation = d.y.atan2(d.x.hypot(d.z));
        texel_of(
            &png,
            0.5 + d.x.atan2(d.z) / (2.0 * PI),
            0.5 - elevation / PI,
            1e-6,
        )
    };
    let (mut sky_pixels, mut ball_pixels, mut white) = (0, 0, 0);
    for (x, y) in picture.pixels() {
        let d = camera.direction(x as f64, y as f64).normalize();
        let got = picture.rgb(x, y);
        match picture.object(x, y) {
            "sky" => {
                let Some(texel) = sky(d) else { continue };
                assert_near(&format!("sky at ({x}, {y})"), got, texel, 1e-6);
                sky_pixels += 1;
                white += usize::from(texel == DVec3::ONE);
            }
            "mirror ball" => {
                let c = DVec3::new(0.0, 0.0, 8.0);
                let Some(t) = sphere_hit(DVec3::ZERO, d, c, 1.0) else {
                    continue;
                };
                let n = (t * d - c).normalize();
                let out = d - 2.0 * d.dot(n) * n;
                if out.y < 0.01 {
                    continue;
                }
                let Some(texel) = sky(out) else { continue };
                assert_near(&format!("ball at ({x}, {y})"), got, 0.9 * texel, 1e-4);
                ball_pixels += 1;
            }
            _ => {}
        }
    }
    assert!(
        sky_pixels > 4000 && ball_pixels > 20 && white > 20,
        "{sky_pixels} sky, {ball_pixels} ball, {white} white"
    );
}

/// scenes/picture-surfaces.toml, with the picture letter-f.png worked out here from each
/// pixel's ray. The wall (plane z = 20, u = x, v = 3 − y, tiled every 2 × 2): diffuse
/// lighting by white lights scales the texel by one factor, so the pixel's colour is a
/// multiple of the texel's. The ball (radius 0.8 at (−1.3, −0.2, 10); u = rφ, v = rθ; size
/// (−2πr, πr) from (0, 0)), shown whatever the lighting: column −φ/2π (repeated), row from the
/// top θ/π, exactly the texel.
#[test]
fn picture_surfaces_show_their_texels() {
    let (w, h) = (160, 120);
    let camera = Camera::new(DVec3::ZERO, DVec3::Z, DVec3::Y, 40.0, w, h);
    let picture = render("picture-surfaces", w, h);
    let png = example_picture("letter-f.png");
    let (mut wall, mut ball) = (0, 0);
    for (x, y) in picture.pixels() {
        let d = camera.direction(x as f64, y as f64).normalize();
        let got = picture.rgb(x, y);
        match picture.object(x, y) {
            "wall" => {
                let p = d * (20.0 / d.z);
                let Some(texel) =
                    texel_of(&png, p.x / 2.0, ((3.0 - p.y) / 2.0).rem_euclid(1.0), 1e-6)
                else {
                    continue;
                };
                let k = got.x / texel.x;
                assert!(k > 0.1, "wall at ({x}, {y}) lit: {got}");
                assert_near(&format!("wall at ({x}, {y})"), got, k * texel, 1e-5);
                wall += 1;
            }
            "ball" => {
                let c = DVec3::new(-1.3, -0.2, 10.0);
                let Some(t) = sphere_hit(DVec3::ZERO, d, c, 0.8) else {
                    continue;
                };
                let q = (t * d - c) / 0.8;
                let (phi, theta) = (q.x.atan2(q.z), q.y.clamp(-1.0, 1.0).acos());
                let Some(texel) = texel_of(&png, -phi / (2.0 * PI), theta / PI, 1e-6) else {
                    continue;
                };
                assert_near(&format!("ball at ({x}, {y})"), got, texel, 1e-5);
                ball += 1;
            }
            _ => {}
        }
    }
    assert!(wall > 8000 && ball > 500, "{wall} wall, {ball} ball");
}

/// scenes/research/AutostereogramResonatorPlanar.toml, Dr TIM's program of that name: seen from
/// the eye at (−3, 0, 0) looking at (0, 0, 50) with up −y (Dr TIM's camera turned by 180°),
/// through the two lenses of focal lengths ±50 just before and after mirror A (which cancel
/// to within 10⁻⁴ of the picture's units), every pixel shows the texel of the tiled picture at
/// the point where its line of sight meets the plane z = 50.0002: u = x, v = y, corner
/// (15, −8), size (−1, 16), columns along −x, rows down +y, lit by white ambient light only
/// (colour = texel). Pixels within 0.02 texels of a texel's edge are left out. The
/// first surface every line of sight meets is the lens in front of A.
#[test]
fn research_autostereogram_resonator_planar_shows_the_wallpaper() {
    let (w, h) = (200, 150);
    let eye = DVec3::new(-3.0, 0.0, 0.0);
    let angle = 2.0 * (20.0 * 400.0 / 300.0 / 2.0 / 50.0_f64).atan().to_degrees();
    let camera = Camera::new(eye, DVec3::new(3.0, 0.0, 50.0), -DVec3::Y, angle, w, h);
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/research/AutostereogramResonatorPlanar.toml");
    let picture = render_file(
        &path,
        &["--width", "200", "--height", "150", "--aov", "object"],
    );
    let png = example_picture("letter-f.png");
    let mut checked = 0;
    for (x, y) in picture.pixels() {
        assert_eq!(picture.object(x, y), "lens in front of mirror A");
        let d = camera.direction(x as f64, y as f64);
        let p = eye + d * (50.0002 / d.z);
        let Some(texel) = texel_of(&png, (p.x - 15.0) / -1.0, (p.y + 8.0) / 16.0, 0.02) else {
            continue;
        };
        assert_near(&format!("pixel ({x}, {y})"), picture.rgb(x, y), texel, 1e-5);
        checked += 1;
    }
    assert!(checked > 20000, "{checked} pixels checked");
}

/// scenes/textured-mesh.toml: a cube from `meshes/textured-cube.obj` with no surface of its
/// own: the file's materials. Its sides (material `checker`, Kd 1 × the texel of
/// `checker.png`: yellow (230, 200, 40), dark blue (30, 40, 120), one white) show both checker
/// colours and no red; its top and bottom (material `red`, Kd 0.8 0.1 0.1) are red wherever
/// seen: more red than green or blue (a white specular highlight aside).
#[test]
fn textured_mesh_scene_shows_the_files_texture_and_colours() {
    let picture = render("textured-mesh", 160, 120);
    let (mut yellow, mut blue, mut red, mut red_part) = (0, 0, 0, 0);
    for (x, y) in picture.pixels() {
        let c = picture.rgb(x, y);
        match picture.object(x, y) {
            "crate/cube (checker)" => {
                if c.x > 2.0 * c.z && c.y > 2.0 * c.z {
                    yellow += 1;
                } else if c.z > c.x && c.z > c.y {
                    blue += 1;
                }
                assert!(
                    !(c.x > 2.0 * c.y && c.x > 2.0 * c.z),
                    "red on a side at ({x}, {y}): {c}"
                );
            }
            "crate/cube (red)" => {
                red_part += 1;
                if c.x > 2.0 * c.y && c.x > 2.0 * c.z {
                    red += 1;
                }
            }
            _ => {}
        }
    }
    assert!(yellow > 100 && blue > 100, "yellow {yellow}, blue {blue}");
    assert!(
        red_part > 50 && red * 10 >= red_part * 9,
        "{red} of {red_part} red"
    );
}

/// scenes/patterns.toml: on the holey pane (z = 11.5, u along +x from x = 0.1, v down from
/// y = 0.2, its 0.8 × 0.8 mask `letter-f.png`, with light holes) a pixel whose ray meets a dark
/// texel (blue below 127/255) shows the pane's matt (0.2, 0.4, 1) lit by white light, so in
/// exactly those proportions, and one that meets a light texel (a hole: the F and the blue
/// quarter) shows what lies behind, in other proportions; on the either-or square (z = 12
/// from x = 1.1), dark texels show matt red and light ones the mirror (the sky and floor, with
/// green in them).
#[test]
fn patterns_holes_and_masks_follow_the_mask_picture() {
    let (w, h) = (320, 240);
    let camera = Camera::standard(20.0, w, h);
    let picture = render("patterns", w, h);
    let png = example_picture("letter-f.png");
    let mask = |z: f64, left: f64, d: DVec3| {
        let p = d * (z / d.z);
        let (u, v) = ((p.x - left) / 0.8, (0.2 - p.y) / 0.8);
        if !(0.0..1.0).contains(&u) || !(0.0..1.0).contains(&v) {
            return None;
        }
        texel_of(&png, u, v, 1e-3).map(|t| t.z < 127.0 / 255.0)
    };
    let (mut holes, mut pane, mut red, mut mirror) = (0, 0, 0, 0);
    for (x, y) in picture.pixels() {
        let d = camera.direction(x as f64, y as f64).normalize();
        let (object, got) = (picture.object(x, y), picture.rgb(x, y));
        let pane_blue = (got / got.z - DVec3::new(0.2, 0.4, 1.0))
            .abs()
            .max_element()
            < 1e-6;
        match mask(11.5, 0.1, d) {
            Some(true) => {
                assert!(pane_blue, "the pane at ({x}, {y}): {got}");
                pane += 1;
            }
            Some(false) => {
                assert!(!pane_blue, "a hole at ({x}, {y}): {got}");
                holes += 1;
            }
            None => {}
        }
        if object == "either-or" {
            match mask(12.0, 1.1, d) {
                Some(true) => {
                    assert!(
                        got.x > 0.0 && got.y == 0.0 && got.z == 0.0,
                        "red at ({x}, {y}): {got}"
                    );
                    red += 1;
                }
                Some(false) => {
                    assert!(got.y > 0.05, "mirror at ({x}, {y}): {got}");
                    mirror += 1;
                }
                None => {}
            }
        }
    }
    assert!(
        holes > 100 && pane > 100 && red > 100 && mirror > 50,
        "{holes} holes, {pane} pane, {red} red, {mirror} mirror"
    );
}

/// scenes/research/WedgeExplorer.toml: a pixel's ray from (0, 0, −10) crosses the three
/// interfaces z = 0, 0.5, 1, each multiplying the index by 1.1, so that the transverse part of
/// its unit direction shrinks by 1.1 at each (Snell's law), and, where it stays inside the
/// wedges' square, meets the backdrop z = 30 at (x, y). There the backdrop's colour is Dr
/// TIM's position-dependent one at the distance |x − y|/√2 from the line through (0, 0, 30)
/// along (1, 1, 0), period 2: c_k = 0.5 + 0.5 sin(πd + 2πk/3). Lit with a white specular
/// colour by white lights, the pixel is a·c + b·(1, 1, 1): two of its channels fix a and b,
/// the third must agree.
#[test]
fn research_wedge_explorer_shows_the_backdrop_where_snell_sends_each_ray() {
    let (w, h) = (160, 120);
    let origin = DVec3::new(0.0, 0.0, -10.0);
    let camera = Camera::new(origin, DVec3::Z, DVec3::Y, 20.0, w, h);
    let picture = render("research/WedgeExplorer", w, h);
    let mut checked = 0;
    for (x, y) in picture.pixels() {
        let mut d = camera.direction(x as f64, y as f64).normalize();
        let mut p = origin + d * (-origin.z / d.z);
        for z in [0.5, 1.0, 30.0] {
            let transverse = DVec3::new(d.x, d.y, 0.0) / 1.1;
            d = transverse + DVec3::Z * (1.0 - transverse.length_squared()).sqrt();
            p += d * ((z - p.z) / d.z);
        }
        if p.x.abs().max(p.y.abs()) > 0.99 {
            continue;
        }
        let distance = (p.x - p.y).abs() / 2f64.sqrt();
        let c = DVec3::from_array(
            [0.0, 1.0, 2.0].map(|k| 0.5 + 0.5 * (PI * distance + k * 2.0 * PI / 3.0).sin()),
        );
        let got = picture.rgb(x, y);
        // a and b from the two channels whose colours differ most.
        let (i, j, k) = if (c.x - c.y).abs() > (c.x - c.z).abs().max((c.y - c.z).abs()) {
            (0, 1, 2)
        } else if (c.x - c.z).abs() > (c.y - c.z).abs() {
            (0, 2, 1)
        } else {
            (1, 2, 0)
        };
        let a = (got[i] - got[j]) / (c[i] - c[j]);
        let b = got[i] - a * c[i];
        assert!(a > 0.0, "({x}, {y}): lit, {got}");
        assert!(
            (a * c[k] + b - got[k]).abs() < 1e-6,
            "({x}, {y}): {got} is not a·{c} + b"
        );
        checked += 1;
    }
    assert!(checked > 50, "{checked} pixels");
}

/// scenes/research/TransmissionCoefficientVisualiser.toml (Dr TIM's FOVSteering program): the
/// window's light is vignetted by the lenslets' apertures, worked out here from the telescope
/// in the (u, a) projection. A ray from the camera of slope s = x/2 (it meets the window 2
/// ahead) crosses lenslet 1 (aperture [−½, ½] in units of f₁) at h and lenslet 2's plane at
/// s − η(s − h) = 1.2 s − 0.2 h (η = −0.2), within [1.2 s − 0.1, 1.2 s + 0.1]; lenslet 2's
/// aperture is [δ − ½, δ + ½] = [0.1, 1.1]. So nothing passes for s ≤ 0 (the window's left half
/// is black) and everything in u for 1/6 ≤ s ≤ 5/6; along v (η = −0.1, δ = 0.1) everything
/// for −0.318 ≤ s_v ≤ 0.5. Where all passes, the camera sees the sky or the floor.
#[test]
fn research_transmission_coefficient_visualiser_vignettes_by_the_apertures() {
    let (w, h) = (64, 48);
    let p = render("research/TransmissionCoefficientVisualiser", w, h);
    // Slopes of pixel centres: the view angle spans the outermost centres.
    let span = 2.0 * (82.76886f64 / 2.0).to_radians().tan() / (w - 1) as f64;
    let (mut black, mut bright) = (0, 0);
    for (x, y) in p.pixels() {
        let su = (x as f64 - (w - 1) as f64 / 2.0) * span;
        let sv = ((h - 1) as f64 / 2.0 - y as f64) * span;
        // On the window, clear of the frame and of the aperture's blur (0.025/2 in slope).
        if su.abs() > 0.48 || sv.abs() > 0.48 {
            continue;
        }
        let c = p.rgb(x, y);
        if su < -0.02 {
            assert_eq!(c, DVec3::ZERO, "({x}, {y}) at slopes ({su}, {sv})");
            black += 1;
        } else if (0.19..0.8).contains(&su) && (-0.29..0.48).contains(&sv) {
            assert!(
                c.min_element() > 0.1,
                "({x}, {y}) at slopes ({su}, {sv}): {c}"
            );
            bright += 1;
        }
    }
    assert!(
        black > 400 && bright > 250,
        "{black} black, {bright} bright"
    );
}

/// scenes/research/PixellationEffectsExplorer.toml (Dr TIM's pixellation explorer, blur only):
/// the pixel-channeling lens has the chart in its focal plane, and an ideal lens focuses all
/// parallel rays to one point of it, so the rays a pixellated plane merely offsets (keeping
/// their directions) see the same chart points as without it; the diffractive blur, which
/// turns them, washes out the fine bars.
#[test]
fn research_pixellation_channeling_lens_removes_the_ray_offset_blur_but_not_diffraction() {
    let name = "research/PixellationEffectsExplorer";
    let set = |blur: bool, offset: bool| {
        let p = scene(name);
        let blur = format!("object.1.surface.simulate_diffractive_blur={blur}");
        let offset = format!("object.1.surface.simulate_ray_offset={offset}");
        let args = ["--width", "160", "--height", "120", "--spp", "4"];
        let args = [&args[..], &["--set", &blur, "--set", &offset]].concat();
        render_file(&p, &args)
    };
    let differing = |a: &Picture, b: &Picture| {
        a.pixels()
            .filter(|&(x, y)| (a.rgb(x, y) - b.rgb(x, y)).abs().max_element() > 1e-3)
            .count()
    };
    let offset_only = set(false, true);
    let clear = set(false, false);
    let blurred = set(true, true);
    assert!(
        differing(&offset_only, &clear) <= 20,
        "{}",
        differing(&offset_only, &clear)
    );
    assert!(
        differing(&blurred, &clear) > 1500,
        "{}",
        differing(&blurred, &clear)
    );
}

/// scenes/research/ViewRotationExplorer.toml (Dr TIM's ray-rotation sheet of two idealised
/// Dove-prism arrays): each array mirrors the direction in a plane perpendicular to its
/// inversion direction, and two mirrors whose normals make the angle θ (here −5°, from x to
/// (cos 5°, −sin 5°, 0)) compose to a rotation by 2θ about their common line (z): every line of
/// sight through the disc leaves turned by −10° about z.
#[test]
fn research_view_rotation_dove_prism_arrays_rotate_the_view_by_twice_their_angle() {
    let start = DVec3::new(0.0, 0.0, -10.0);
    let targets: Vec<DVec3> = (0..25)
        .map(|k| {
            DVec3::new(
                -0.6 + 0.3 * (k % 5) as f64,
                -0.6 + 0.3 * (k / 5) as f64,
                0.0,
            )
        })
        .collect();
    let rays: Vec<String> = targets
        .iter()
        .enumerate()
        .map(|(k, t)| ray(k, start, *t - start))
        .collect();
    let traced = trace("research/ViewRotationExplorer", &rays);
    assert_eq!(traced.len(), targets.len());
    let turn = glam::DQuat::from_rotation_z(-10f64.to_radians());
    for (ray, target) in traced.iter().zip(&targets) {
        let second = ray
            .points
            .iter()
            .position(|p| p.object.as_deref() == Some("Dove-prism array 2"))
            .unwrap_or_else(|| panic!("{ray:?}"));
        assert_eq!(
            ray.points[second - 2].object.as_deref(),
            Some("Dove-prism array 1")
        );
        let d = (*target - start).normalize();
        assert_near("after the sheet", leaving(ray, second + 1), turn * d, 1e-9);
    }
}

/// scenes/research/DerivativeControlSurfaceExplorer.toml (Dr TIM's pixellated view rotator):
/// a line of sight from the eye (0, 0, −5) through the centre of a 0.1 × 0.1 pixel of the plane
/// z = 0 leaves towards the point where it would have met the plane z = 10, turned by 20° about
/// the z axis (the line through the eye along the plane's normal), worked out here; a line of
/// sight through another point of the same pixel leaves parallel to it.
#[test]
fn research_derivative_control_surface_explorer_turns_the_view_by_20_degrees() {
    let eye = DVec3::new(0.0, 0.0, -5.0);
    let centres = [(0.3, 0.1), (-0.2, 0.4), (0.0, -0.5), (0.6, 0.6)];
    let mut rays: Vec<String> = Vec::new();
    for (k, &(x, y)) in centres.iter().enumerate() {
        rays.push(ray(2 * k, eye, DVec3::new(x, y, 5.0)));
        // Through the same pixel, 0.03 off its centre: parallel to the pixel centre's own
        // outgoing ray, which starts 0.03 away.
        rays.push(ray(2 * k + 1, eye, DVec3::new(x + 0.03, y - 0.02, 5.0)));
    }
    let traced = trace("research/DerivativeControlSurfaceExplorer", &rays);
    let turn = glam::DQuat::from_rotation_z(20f64.to_radians());
    for (k, &(x, y)) in centres.iter().enumerate() {
        let p = DVec3::new(x, y, 0.0);
        // The apparent point: the line of sight meets z = 10 at E + 3 (P − E).
        let apparent = eye + 3.0 * (p - eye);
        let expected = (turn * apparent - p).normalize();
        let ray = &traced[2 * k];
        assert_eq!(
            ray.points[1].object.as_deref(),
            Some("derivative-control surface"),
            "{ray:?}"
        );
        assert_near("through a pixel centre", leaving(ray, 2), expected, 1e-9);
        let ray = &traced[2 * k + 1];
        let d = DVec3::new(0.03, -0.02, 0.0) / 5.0;
        let off = leaving(ray, 2);
        // The tangential change is the same as at the centre (J = 1 about the pixel's own
        // central directions): the outgoing direction differs from the centre's by the
        // incident one's change, d, in x and y.
        let centre = leaving(&traced[2 * k], 2);
        let incident = |v: DVec3| v.normalize();
        let change = incident(DVec3::new(x, y, 5.0) + 5.0 * d) - incident(DVec3::new(x, y, 5.0));
        assert!(
            ((off - centre).truncate() - change.truncate()).length() < 1e-9,
            "pixel {k}: {off} vs {centre}"
        );
    }
}

/// scenes/research/CurlVisualiser.toml (Dr TIM's curl visualiser with an optical vortex): the
/// vortex's light at distance r from its line travels along −z tilted azimuthally by
/// |m/k|/r = 0.1/r; the ray-rotation sheet turns that by 90° into a radial tilt, and the
/// camera 5 in front sees light leaving the window at r towards it, tilted by r/5. So the field
/// lights up only near the ring 0.1/r = r/5, r = √0.5: there (within 0.004 in r, where the
/// tilts differ by under a tenth of the 1° fuzziness) the glow is nearly the field's full red,
/// and beyond 0.03 (where they differ by more than half the fuzziness) there is none.
#[test]
fn research_curl_visualiser_shows_the_vortex_ring_where_the_turned_rays_meet_the_eye() {
    let (w, h) = (160, 120);
    let name = "research/CurlVisualiser";
    let args = ["--width", "160", "--height", "120", "--spp", "1"];
    let lit = render_file(&scene(name), &args);
    let dark = render_file(
        &scene(name),
        &[&args[..], &["--set", "object.2.surface.colour=[0,0,0]"]].concat(),
    );
    let pitch = 2.0 * 16f64.to_radians().tan() / (w - 1) as f64;
    let ring = 0.5f64.sqrt();
    let (mut on, mut off) = (0, 0);
    for (x, y) in lit.pixels() {
        // Where the pixel centre's ray meets the window, 5 ahead.
        let r = 5.0
            * pitch
            * ((x as f64 - (w - 1) as f64 / 2.0).hypot(y as f64 - (h - 1) as f64 / 2.0));
        let glow = lit.rgb(x, y) - dark.rgb(x, y);
        if (r - ring).abs() < 0.004 {
            assert!(
                glow.x > 0.8 && glow.y.abs() < 1e-6,
                "({x}, {y}) at r = {r}: {glow}"
            );
            on += 1;
        } else if (r - ring).abs() > 0.03 && r < 0.95 {
            assert_eq!(glow, DVec3::ZERO, "({x}, {y}) at r = {r}");
            off += 1;
        }
    }
    assert!(on >= 8 && off > 5000, "{on} on the ring, {off} off it");
}

/// scenes/research/FourPiLensInsideView.toml (Dr TIM's movie of that name): frame k looks
/// along (cos φ, 0, sin φ), φ = 2π k / 51, as the program's populateStudio sets it; and with
/// the program's focal length 1e5 the 4π lens images outside space to itself, so its view from
/// inside is, but for the lenses' frames, the view through undeviating panes of the same
/// transmission (lens_type = "glass-pane"): the lenses turn rays by |r|/f ≈ 1e-5 at most.
#[test]
fn research_four_pi_lens_inside_view_turns_as_dr_tim_and_shows_the_world_undistorted() {
    let path = scene("research/FourPiLensInsideView");
    let text = std::fs::read_to_string(&path).unwrap();
    let file: toml::Table = text.parse().unwrap();
    let keyframes = file["animation"]["track"][0]["keyframes"]
        .as_array()
        .unwrap();
    assert_eq!(file["animation"]["frames"].as_integer(), Some(50));
    assert_eq!(keyframes.len(), 50);
    for (k, keyframe) in keyframes.iter().enumerate() {
        assert_eq!(keyframe["frame"].as_integer(), Some(k as i64));
        let phi = 2.0 * PI * k as f64 / 51.0;
        let d = vector(&serde_json::to_value(&keyframe["value"]).unwrap());
        assert!(
            (d - DVec3::new(phi.cos(), 0.0, phi.sin())).length() < 1e-15,
            "frame {k}: {d}"
        );
    }
    let frame = |k: &str, lens_type: &str| {
        let dir = TempDir::new().unwrap();
        let set = format!("device.0.lenses.lens_type=\"{lens_type}\"");
        let args = [
            "render",
            "-q",
            path_str(&path),
            "-o",
            "f.exr",
            "--frame",
            k,
            "--width",
            "160",
            "--height",
            "120",
            "--set",
            &set,
        ];
        timbre(dir.path(), &args).assert_success();
        Picture::read(&dir.path().join(format!("f-{:0>4}.exr", k)))
    };
    for k in ["7", "30"] {
        let lenses = frame(k, "ideal-thin-lens");
        let panes = frame(k, "glass-pane");
        let differing = lenses
            .pixels()
            .filter(|&(x, y)| (lenses.rgb(x, y) - panes.rgb(x, y)).abs().max_element() > 2e-3)
            .count();
        assert!(
            differing <= 40,
            "frame {k}: {differing} of 19200 pixels differ"
        );
    }
}

/// scenes/research/SurroundAnaglyphCameraDemo.toml (Dr TIM's surround-anaglyph camera): the
/// eyes, 1 apart on a horizontal circle about (0, 2, 0) and looking along its tangents, see
/// the green ball at (3, 0, 0), 3 away horizontally, at the azimuths 90° ± asin(0.5 / 3) (the
/// left eye to the right), whatever its height: 2 asin(1/6) of the 960 columns' 360° apart.
#[test]
fn research_surround_anaglyph_eyes_see_the_near_ball_at_the_tangent_azimuths() {
    let p = render_file(
        &scene("research/SurroundAnaglyphCameraDemo"),
        &["--set", "camera.stereo=\"top-bottom\""],
    );
    let (w, h) = (960, 480);
    assert_eq!(p.size, (w, 2 * h));
    // The ball's pixels: green, below 20° under the horizon, within 30° of the right.
    let column = |top: usize| {
        let (mut sum, mut n) = (0.0, 0.0);
        for y in top + h * 110 / 180..top + h {
            for x in w * 225 / 360..w * 315 / 360 {
                let c = p.rgb(x, y);
                if c.y > 0.1 && c.y > 2.0 * c.x && c.y > 2.0 * c.z {
                    sum += x as f64;
                    n += 1.0;
                }
            }
        }
        assert!(n > 100.0, "{n} green pixels");
        sum / n
    };
    let (left, right) = (column(0), column(h));
    let expected = 2.0 * (1.0f64 / 6.0).asin() / (2.0 * PI) * w as f64;
    assert!(
        (left - right - expected).abs() < 1.0,
        "left eye {left}, right eye {right}: {} apart, expected {expected}",
        left - right
    );
    // Between them, straight to the right (column 3W/4 − ½).
    let middle = 0.5 * (left + right);
    assert!((middle - 719.5).abs() < 1.0, "{middle}");
}

/// scenes/research/NegativeSpaceWedgeStarTrajectoryPlotter.toml (Dr TIM's program of that
/// name): the wedges' sheets rotate ray directions by 180° about their normals, minus the
/// mirror in planes through the star's axis, so every straight piece of the trajectory lies on a
/// line as far from the axis as the first, from (0, 0, 1) along (cos 2°, 0, sin 2°): cos 2°. It
/// crosses the wedges round the axis, each wedge's two sheets one after the other.
#[test]
fn research_negative_space_wedge_trajectory_keeps_its_distance_from_the_axis() {
    let rays = trace_file(&scene("research/NegativeSpaceWedgeStarTrajectoryPlotter"));
    assert_eq!(rays.len(), 2);
    let expected = 2f64.to_radians().cos();
    for ray in &rays {
        assert!(ray.points.len() > 20, "{}", ray.points.len());
        let sheets: Vec<&str> = ray.points[1..]
            .iter()
            .filter_map(|p| p.object.as_deref())
            .filter(|o| o.contains("sheet"))
            .collect();
        assert!(sheets.len() > 20, "{sheets:?}");
        for pair in ray.points.windows(2) {
            let (a, b) = (pair[0].position, pair[1].position);
            // The distance of the line through a and b from the y axis, in the plane y = 0.
            let (p, d) = (
                glam::DVec2::new(a.x, a.z),
                glam::DVec2::new(b.x - a.x, b.z - a.z),
            );
            let distance = p.perp_dot(d.normalize()).abs();
            assert!(
                (distance - expected).abs() < 1e-9,
                "{} to {}: {distance} from the axis",
                a,
                b
            );
            assert!(a.y.abs() < 1e-9, "{a}");
        }
        // It starts inside wedge 1 (centred on +z), leaves through one of its sheets, then
        // crosses each wedge's two sheets in a row.
        assert!(sheets[0].ends_with("wedge 1 sheet 2") || sheets[0].ends_with("wedge 1 sheet 1"));
        for pair in sheets[1..].chunks(2).filter(|c| c.len() == 2) {
            let wedge = |s: &str| s.split(" sheet").next().unwrap().to_string();
            assert_eq!(wedge(pair[0]), wedge(pair[1]), "{pair:?}");
        }
    }
}

/// scenes/research/NetOfHypercubeVisualiser.toml (Dr TIM's program of that name): the
/// trajectory from the inner cube's centre is a straight line in the tesseract's surface. Its
/// 4D direction is constant; in each cube's 3D coordinates it is that direction less the cube's
/// normal component, and the wedges, which turn by 90° or 180° about axes along the net's
/// edges, only permute and negate the components. So every straight segment's direction has
/// the start direction's components, (0.1, 1, 0)/|…|, in some order and with some signs.
#[test]
fn research_net_of_hypercube_trajectory_is_straight_in_the_tesseract() {
    let rays = trace_file(&scene("research/NetOfHypercubeVisualiser"));
    assert_eq!(rays.len(), 1);
    let ray = &rays[0];
    let sorted = |d: DVec3| {
        let mut c = [d.x.abs(), d.y.abs(), d.z.abs()];
        c.sort_by(f64::total_cmp);
        c
    };
    let expected = sorted(DVec3::new(0.1, 1.0, 0.0).normalize());
    let mut segments = 0;
    for pair in ray.points.windows(2) {
        if pair[1].arrival == "teleported" {
            continue;
        }
        let d = (pair[1].position - pair[0].position).normalize();
        let got = sorted(d);
        assert!(
            got.iter().zip(&expected).all(|(a, b)| (a - b).abs() < 1e-9),
            "{} to {}: direction {d}",
            pair[0].position,
            pair[1].position
        );
        segments += 1;
    }
    let teleports = ray
        .points
        .iter()
        .filter(|p| p.arrival == "teleported")
        .count();
    assert!(
        teleports >= 5 && segments > 12,
        "{teleports} teleports, {segments} segments"
    );
    // Both kinds of wedge glue it: the outer cubes' sides (90°) and the pyramids' (180°).
    for kind in ["90° wedge", "180° wedge"] {
        assert!(
            ray.points
                .iter()
                .any(|p| p.object.as_deref().is_some_and(|o| o.contains(kind))),
            "{kind}"
        );
    }
}

/// scenes/research/NetOfSymmetric4SimplexVisualiser.toml (Dr TIM's program of that name): the
/// inner tetrahedron's vertices are alternate corners of the cube of side 1/√2 about the origin,
/// and round each of its edges three regular tetrahedra leave 360° − 3 arccos ⅓ for the wedge.
/// So each time the trajectory is teleported from a wedge's leg, at the edge from vertex I to
/// vertex J, it leaves the other leg on its line turned by that angle about that edge.
#[test]
fn research_net_of_4_simplex_trajectory_turns_by_the_deficit_angle() {
    let rays = trace_file(&scene("research/NetOfSymmetric4SimplexVisualiser"));
    let ray = &rays[0];
    let h = 0.5 / std::f64::consts::SQRT_2;
    let v = [
        DVec3::new(h, h, h),
        DVec3::new(h, -h, -h),
        DVec3::new(-h, h, -h),
        DVec3::new(-h, -h, h),
    ];
    let nu = TAU - 3.0 * (1.0f64 / 3.0).acos();
    let rotate = |p: DVec3, axis: DVec3, angle: f64| {
        p * angle.cos() + axis.cross(p) * angle.sin() + axis * axis.dot(p) * (1.0 - angle.cos())
    };
    let mut teleports = 0;
    for k in 2..ray.points.len() - 1 {
        if ray.points[k].arrival != "teleported" {
            continue;
        }
        let (before, at, after, next) = (
            ray.points[k - 2].position,
            ray.points[k - 1].position,
            ray.points[k].position,
            ray.points[k + 1].position,
        );
        let object = ray.points[k - 1].object.as_deref().unwrap();
        let edge = object.split("wedge at edge ").nth(1).unwrap();
        let i: usize = edge[..1].parse().unwrap();
        let j: usize = edge[2..3].parse().unwrap();
        let axis = (v[j] - v[i]).normalize();
        let (d_in, d_out) = ((at - before).normalize(), (next - after).normalize());
        let turned = [nu, -nu].iter().any(|&a| {
            (v[i] + rotate(at - v[i], axis, a) - after).length() < 1e-9
                && (rotate(d_in, axis, a) - d_out).length() < 1e-9
        });
        assert!(turned, "at {at} on {object}: to {after} along {d_out}");
        teleports += 1;
    }
    assert!(teleports >= 5, "{teleports} teleports");
}

/// scenes/research/ShiftyGCLAsCubicCloakVisualiser.toml (Dr TIM's program of that name): the
/// inner cube of the cloak is seen shifted by δ = (0, 0.2, 0) and the space round it as it is.
/// So each trajectory along +x at height y runs at y − 0.2 where it crosses the inner cube
/// (|x| < 0.4), and leaves the cloak on the line it came on.
#[test]
fn research_shifty_cloak_trajectories_run_lower_inside_and_straight_on_outside() {
    let rays = trace_file(&scene("research/ShiftyGCLAsCubicCloakVisualiser"));
    assert_eq!(rays.len(), 3);
    let mut inside = 0;
    for (ray, y) in rays.iter().zip([0.3, 0.0, -0.3]) {
        assert!(
            (ray.direction - DVec3::X).length() < 1e-9,
            "{}",
            ray.trajectory
        );
        let last = ray.points.last().unwrap().position;
        assert!(
            (last.y - y).abs() < 1e-9 && (last.z - 0.01).abs() < 1e-9,
            "{}: ends at {last}",
            ray.trajectory
        );
        for p in &ray.points {
            let p = p.position;
            if p.x.abs() < 0.4 + 1e-9 && (p.y - (y - 0.2)).abs() < 0.4 {
                assert!((p.y - (y - 0.2)).abs() < 1e-9, "{}: {p}", ray.trajectory);
                inside += 1;
            }
        }
    }
    // The two upper trajectories cross the inner cube (entering and leaving it); the lowest,
    // at −0.5 inside, passes below it.
    assert_eq!(inside, 4);
}

/// scenes/research/CubeInRayRotationSheetStar.toml (Dr TIM's program of that name): each of the
/// eight sheets turns a ray's direction by 44° about the star's axis oriented along the
/// crossing, so a line of sight from the eye that goes round the axis through sheet after sheet
/// has turned by 44° k after k sheets, and after all eight by 352°: 8° short of a whole turn.
#[test]
fn research_cube_in_ray_rotation_sheet_star_turns_lines_of_sight_by_44_degrees_a_sheet() {
    let start = DVec3::new(1.0, 0.0, 0.01);
    let d0 = DVec3::new(-0.3, 0.0, 1.0).normalize();
    let rays = trace("research/CubeInRayRotationSheetStar", &[ray(0, start, d0)]);
    let points = &rays[0].points;
    let sheets: Vec<usize> = (1..points.len())
        .filter(|&k| {
            points[k]
                .object
                .as_deref()
                .is_some_and(|o| o.contains("ray-rotation sheet"))
        })
        .collect();
    assert!(sheets.len() >= 8, "{:?}", rays[0].points);
    // The first sheet crossed, and the sense of the turns: about +y if the ray crosses it
    // along its normal (towards increasing azimuth, the star's ŵ × r̂ with ŵ = +y), else −y.
    let first = points[sheets[0]].position;
    let normal = DVec3::Y.cross(DVec3::new(first.x, 0.0, first.z).normalize());
    let axis = if d0.dot(normal) > 0.0 {
        DVec3::Y
    } else {
        -DVec3::Y
    };
    for (k, &index) in sheets.iter().take(8).enumerate() {
        let next = points.get(index + 1).map_or(rays[0].direction, |p| {
            (p.position - points[index].position).normalize()
        });
        let turn = (44.0 * (k + 1) as f64).to_radians();
        let expected = d0 * turn.cos() + axis.cross(d0) * turn.sin();
        assert!(
            (next - expected).length() < 1e-9,
            "after sheet {}: {next}, expected {expected}",
            k + 1
        );
    }
}

/// scenes/research/SpaceAroundBlackHoleVisualiser.toml (Dr TIM's program of that name): the
/// black hole's shadow. For Chen's profile (j = 1) n r is least at the photon sphere
/// r = (2 + √3)R, and a line of sight with impact parameter b (n r sin θ, conserved, also
/// across the simulation sphere's surface by Snell's law) below n r there falls in. Seen from
/// the eye, 10 from the hole, the shadow is the disc of angular radius asin(b_c/10): lines of
/// sight 10 % inside it are black, those 10 % outside see the scene, in every direction round
/// it.
#[test]
fn research_black_hole_shadow_has_the_photon_spheres_angular_radius() {
    let (w, h) = (640, 480);
    let p = render("research/SpaceAroundBlackHoleVisualiser", w, h);
    let view = DVec3::new(-0.3, -0.2, 1.0);
    let eye = -10.0 * view.normalize();
    let camera = Camera::new(eye, view, DVec3::Y, 20.0, w, h);
    let horizon = 0.01;
    let r = (2.0 + 3f64.sqrt()) * horizon;
    let n = (horizon + r).powi(3) / (r * r * (r - horizon));
    let alpha = (n * r / 10.0).asin();
    let forward = view.normalize();
    let across = DVec3::Y.cross(forward).normalize();
    let upwards = forward.cross(across);
    for k in 0..12 {
        let turn = TAU * k as f64 / 12.0;
        let side = turn.cos() * across + turn.sin() * upwards;
        for (factor, black) in [(0.9, true), (1.1, false)] {
            let a = factor * alpha;
            let d = a.cos() * forward + a.sin() * side;
            let (x, y) = camera.pixel_of_direction(d);
            let c = p.rgb(x.round() as usize, y.round() as usize);
            assert_eq!(
                c.max_element() == 0.0,
                black,
                "at {factor} of the shadow's radius, azimuth {k}: {c}"
            );
        }
    }
}
