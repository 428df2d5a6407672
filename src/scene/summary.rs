//! What `timbre check` says about a scene: counts, bounds, camera, output.

use std::fmt;

use glam::DVec3;

use super::{SceneDescription, Stereo};
use crate::geometry::Shape;
use crate::math::ReferenceFrame;
use crate::picture::Picture;

/// Counts and bounds of a scene's geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSummary {
    pub objects: usize,
    /// Triangles of all meshes, counting every copy in arrays.
    pub triangles: u64,
    /// Copies of objects placed by arrays (Embree instances).
    pub instances: u64,
    /// Bounding box of all bounded objects and their copies, if there are any.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Objects without bounds (planes).
    pub unbounded: usize,
}

impl SceneDescription {
    /// Counts and bounds of the scene's geometry.
    pub fn summary(&self) -> SceneSummary {
        let mut copies = vec![(1u64, DVec3::ZERO, DVec3::ZERO); self.objects.len()];
        let mut instances = 0;
        for a in &self.arrays {
            let lo = a.offsets.iter().fold(DVec3::INFINITY, |m, &o| m.min(o));
            let hi = a.offsets.iter().fold(DVec3::NEG_INFINITY, |m, &o| m.max(o));
            for c in &mut copies[a.objects.clone()] {
                *c = (a.offsets.len() as u64, lo, hi);
            }
            instances += a.offsets.len() as u64;
        }
        let mut summary = SceneSummary {
            objects: self.objects.len(),
            triangles: 0,
            instances,
            bounds: None,
            unbounded: 0,
        };
        for (o, &(n, lo, hi)) in self.objects.iter().zip(&copies) {
            if let Shape::TriangleMesh(m) = &o.shape {
                summary.triangles += n * m.triangles().len() as u64;
            }
            match o.shape.bounds() {
                Some(_) if n == 0 => {}
                Some((a, b)) => {
                    let (l, h) = summary
                        .bounds
                        .unwrap_or((DVec3::INFINITY, DVec3::NEG_INFINITY));
                    summary.bounds = Some((l.min(a + lo), h.max(b + hi)));
                }
                None => summary.unbounded += 1,
            }
        }
        summary
    }

    /// The distinct pictures the scene's surfaces show (a picture file named several times
    /// is read once and held once).
    pub fn pictures(&self) -> Vec<&Picture> {
        let mut pictures: Vec<&Picture> = Vec::new();
        for p in self.objects.iter().flat_map(|o| o.surface.pictures()) {
            if !pictures.contains(&p) {
                pictures.push(p);
            }
        }
        pictures
    }

    /// Bytes of memory the scene's pictures hold.
    pub fn picture_bytes(&self) -> u64 {
        self.pictures().iter().map(|p| p.bytes()).sum()
    }

    /// Bytes that building the scene adds to what its description holds, generously: Embree's
    /// geometry and BVH and timbre's tables, measured with Embree 3.13.5 at about 520 bytes an
    /// array copy (counted as 640), 120 a mesh triangle (each prototype once) and 600 an
    /// object. The pictures are not counted: the description holds them already, read only
    /// where the memory was there ([`Picture::load`]), and building shares them.
    pub fn build_memory(&self) -> u64 {
        let triangles: u64 = self
            .objects
            .iter()
            .map(|o| match &o.shape {
                Shape::TriangleMesh(m) => m.triangles().len() as u64,
                _ => 0,
            })
            .sum();
        let copies: u64 = self.arrays.iter().map(|a| a.offsets.len() as u64).sum();
        copies * 640 + triangles * 128 + self.objects.len() as u64 * 640
    }

    /// The whole `timbre check` report (after its "OK" line), one item a line.
    pub fn report(&self) -> Report<'_> {
        Report(self)
    }
}

/// How many objects of each kind of shape the scene has, in order of first appearance:
/// "3 sphere, 1 difference, 2 transformed cone".
fn shape_counts(d: &SceneDescription) -> String {
    let mut counts: Vec<(String, usize)> = Vec::new();
    for o in &d.objects {
        let kind = match &o.shape {
            Shape::Transformed(t) => format!("transformed {}", t.inner().kind()),
            s => s.kind().to_string(),
        };
        match counts.iter_mut().find(|(k, _)| *k == kind) {
            Some((_, n)) => *n += 1,
            None => counts.push((kind, 1)),
        }
    }
    if counts.is_empty() {
        return "none".into();
    }
    counts
        .iter()
        .map(|(k, n)| format!("{n} {k}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A scene description in words (see [`SceneDescription::report`]).
pub struct Report<'a>(&'a SceneDescription);

impl fmt::Display for Report<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let d = self.0;
        let s = d.summary();
        writeln!(f, "  objects:      {}", s.objects)?;
        writeln!(f, "  triangles:    {}", s.triangles)?;
        writeln!(
            f,
            "  instances:    {} (in {} arrays)",
            s.instances,
            d.arrays.len()
        )?;
        match s.bounds {
            None => writeln!(
                f,
                "  bounding box: none ({} unbounded objects)",
                s.unbounded
            )?,
            Some((lo, hi)) => {
                let unbounded = match s.unbounded {
                    0 => String::new(),
                    n => format!(" (and {n} unbounded)"),
                };
                writeln!(
                    f,
                    "  bounding box: [{}, {}, {}] to [{}, {}, {}]{unbounded}",
                    lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
                )?
            }
        }
        writeln!(f, "  shapes:       {}", shape_counts(d))?;
        writeln!(f, "  point lights: {}", d.lights.points.len())?;
        let pictures = d.pictures().len();
        if pictures > 0 {
            writeln!(
                f,
                "  pictures:     {pictures} ({:.2} MiB)",
                d.picture_bytes() as f64 / f64::from(1 << 20)
            )?;
        }
        if !d.trajectories.is_empty() {
            let rays: usize = d.trajectories.iter().map(|t| t.rays().len()).sum();
            writeln!(f, "  trajectories: {} ({rays} rays)", d.trajectories.len())?;
        }
        write!(
            f,
            "  camera:       {}",
            d.camera.describe(d.focus_surface.len())
        )?;
        let moving = d
            .objects
            .iter()
            .filter(|o| o.frame == ReferenceFrame::Camera)
            .count();
        if moving > 0 {
            write!(f, "; {moving} objects moving with it")?;
        }
        if d.stereo != Stereo::Mono {
            write!(f, "; stereo {}", d.stereo.name())?;
        }
        let r = &d.render;
        write!(
            f,
            "\n  render:       {}x{} at {} spp",
            r.width, r.height, r.spp
        )?;
        if let Some(a) = &d.animation {
            write!(
                f,
                "\n  movie:        frames {} to {} of {}, {} track(s), {} fps",
                a.first_frame,
                a.last_frame,
                a.frames,
                a.tracks.len(),
                a.fps
            )?;
        }
        Ok(())
    }
}
