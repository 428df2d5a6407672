//! Ray trajectories: TIM "can visualise ray trajectories" (the paper's program summary). Rays
//! start at a given point and direction (one ray, a cone of rays, or a parallel bundle), are
//! followed forwards through the scene by the same surface laws the renderer applies
//! ([`crate::surfaces::Redirection`]), and every point where they meet a surface is recorded.
//! The recorded paths are drawn into the scene as chains of thin capped cylinders.
//!
//! Trajectories are traced through the scene-frame objects, before the cylinders are added,
//! so no trajectory meets another's cylinders. [`draw`] does both before the scene is built.

mod follow;
mod tubes;

use std::borrow::Cow;

pub use follow::trace;
pub use tubes::tubes;

use glam::DVec3;
use serde::Serialize;
use thiserror::Error;

use crate::embree::{Device, EmbreeError};
use crate::scene::SceneDescription;

/// Why ray trajectories could not be traced.
#[derive(Debug, Error)]
pub enum TrajectoryError {
    #[error(transparent)]
    Embree(#[from] EmbreeError),
    /// Counted in the order of the file: `trajectory` names the ray trajectory that went past.
    #[error(
        "ray trajectory '{trajectory}': with it the ray trajectories have more than {MAX_POINTS} points in all; give fewer rays or a smaller max_interactions"
    )]
    TooManyPoints { trajectory: String },
}

/// `description` with its ray trajectories traced and drawn in as objects ([`tubes`]), and no
/// trajectory sources left: what [`crate::scene::Scene::build`] takes. A description without
/// trajectories is returned as it is.
pub fn draw<'a>(
    device: &Device,
    description: &'a SceneDescription,
) -> Result<Cow<'a, SceneDescription>, TrajectoryError> {
    if description.trajectories.is_empty() {
        return Ok(Cow::Borrowed(description));
    }
    let traced = trace(device, description)?;
    let mut drawn = description.clone();
    drawn
        .objects
        .extend(tubes(&description.trajectories, &traced));
    drawn.trajectories.clear();
    Ok(Cow::Owned(drawn))
}

/// Most points the trajectories of one scene may have in all (some 25 MB of points and, drawn,
/// about a gigabyte of cylinders at worst).
pub const MAX_POINTS: usize = 500_000;

/// Most points kept of a curved path through one lens, evenly spaced along the integrator's
/// steps (a typical crossing takes about a hundred).
pub const MAX_CURVED_POINTS: usize = 256;

/// One ray's recorded path.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Index of the [`crate::scene::RayTrajectory`] in the scene that started it.
    pub source: usize,
    /// Which of the source's rays it is.
    pub ray: usize,
    /// The start, then every point where the ray met a surface (and the points of curved
    /// paths inside gradient-index lenses), in order.
    pub points: Vec<Point>,
    pub end: End,
    /// The unit direction the ray travels in after its last point (for an absorbed or lost ray,
    /// the direction it arrived in).
    pub direction: DVec3,
}

/// Traced rays as `timbre trace --json` writes them and Python's `Scene.trajectories()` returns
/// them (the one format of both): per ray its trajectory's name, its index, its points (how
/// the ray arrived there, the object there by name, the position) and how it ended. Fields are
/// in alphabetical order, as JSON tools print them.
#[derive(Debug, Serialize)]
pub struct TracedRay<'a> {
    pub direction: [f64; 3],
    pub end: &'static str,
    pub points: Vec<TracedPoint<'a>>,
    pub ray: usize,
    pub trajectory: &'a str,
}

/// A point of a [`TracedRay`].
#[derive(Debug, Serialize)]
pub struct TracedPoint<'a> {
    pub arrival: &'static str,
    pub object: Option<&'a str>,
    pub position: [f64; 3],
}

/// The rays `traced` in `description`, named by its trajectories and objects.
pub fn traced_rays<'a>(
    description: &'a SceneDescription,
    traced: &[Trajectory],
) -> Vec<TracedRay<'a>> {
    let object = |o: Option<usize>| o.map(|i| description.objects[i].name.as_str());
    traced
        .iter()
        .map(|t| TracedRay {
            direction: t.direction.to_array(),
            end: t.end.name(),
            points: t
                .points
                .iter()
                .map(|p| TracedPoint {
                    arrival: p.arrival.name(),
                    object: object(p.object),
                    position: p.position.to_array(),
                })
                .collect(),
            ray: t.ray,
            trajectory: &description.trajectories[t.source].name,
        })
        .collect()
}

/// A point of a trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub position: DVec3,
    /// How the ray got here from the previous point.
    pub arrival: Arrival,
    /// The description index of the object whose surface the point lies on; `None` for the
    /// start, points inside a lens, a teleporter's destination and the end of an escaping ray.
    pub object: Option<usize>,
}

/// How a ray got from one recorded point to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arrival {
    /// The first point.
    Start,
    /// In a straight line through space.
    Straight,
    /// Across a lens whose law maps entry to exit in closed form (§3): the straight chord
    /// stands for a path the law does not give.
    Chord,
    /// Along the curved path through a gradient-index lens (integrated) or a
    /// transformation-optics shifter (exact).
    Curved,
    /// Teleported: no path between.
    Teleported,
}

/// Why a trajectory ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// On a surface with a colour of its own (lit or emitting), at the last point.
    Absorbed,
    /// No light comes back along the ray: trapped in a lens, or teleported beyond the
    /// destination's edge (at the last point).
    Lost,
    /// It met nothing more; the last point is where the drawing of it stops (see [`trace`]).
    Escaped,
    /// It met `max_interactions` surfaces and would go on from the last point.
    MaxInteractions,
}

impl Arrival {
    pub fn name(self) -> &'static str {
        match self {
            Arrival::Start => "start",
            Arrival::Straight => "straight",
            Arrival::Chord => "chord",
            Arrival::Curved => "curved",
            Arrival::Teleported => "teleported",
        }
    }
}

impl End {
    pub fn name(self) -> &'static str {
        match self {
            End::Absorbed => "absorbed",
            End::Lost => "lost",
            End::Escaped => "escaped",
            End::MaxInteractions => "max-interactions",
        }
    }
}
