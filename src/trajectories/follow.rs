//! Following rays forwards through a scene, recording where they meet surfaces.

use glam::DVec3;

use super::{Arrival, End, Point, Trajectory};
use crate::embree::{Device, EmbreeError};
use crate::math::Ray;
use crate::render::Interaction;
use crate::scene::{ReferenceFrame, SceneDescription, World};
use crate::surfaces::Redirection;

/// Follows every ray of every trajectory source of `description` through its scene-frame
/// objects, in order of the sources and their rays.
pub fn trace(
    device: &Device,
    description: &SceneDescription,
) -> Result<Vec<Trajectory>, EmbreeError> {
    let world = World::build(device, description, ReferenceFrame::Scene)?;
    let bounds = description.summary().bounds;
    Ok(description
        .trajectories
        .iter()
        .enumerate()
        .flat_map(|(s, source)| {
            let world = &world;
            source.rays().into_iter().enumerate().map(move |(k, ray)| {
                let mut t = follow(world, ray, source.max_interactions, bounds);
                (t.source, t.ray) = (s, k);
                t
            })
        })
        .collect())
}

/// The path of `ray` through `world` (its source and index set to 0), until it is absorbed or
/// lost, meets nothing more, or has met `max_interactions` surfaces. Every surface applies its
/// law exactly as the renderer does to a ray arriving the same way; for the reciprocal laws
/// that is the path light takes.
///
/// A ray that meets nothing is drawn on to beyond the farthest corner of `bounds` (the bounding
/// box of the scene's bounded objects) from its last point, and at least a distance of 1.
pub fn follow(
    world: &World,
    ray: Ray,
    max_interactions: u32,
    bounds: Option<(DVec3, DVec3)>,
) -> Trajectory {
    let mut points = vec![Point {
        position: ray.origin,
        arrival: Arrival::Start,
        object: None,
    }];
    let finish = |points, end, direction| Trajectory {
        source: 0,
        ray: 0,
        points,
        end,
        direction,
    };
    let (mut ray, mut t_min) = (ray, 0.0);
    for level in (1..=max_interactions).rev() {
        let Some(hit) = world
            .geometry
            .nearest(ray.origin, ray.direction, t_min, f64::INFINITY)
        else {
            points.push(Point {
                position: ray.at(escape_length(bounds, ray.origin)),
                arrival: Arrival::Straight,
                object: None,
            });
            return finish(points, End::Escaped, ray.direction);
        };
        let object = &world.objects[hit.object];
        let at = Interaction {
            ray,
            hit,
            geometry: &world.geometry,
            frame: ReferenceFrame::Scene,
            level,
        };
        points.push(Point {
            position: at.point(),
            arrival: Arrival::Straight,
            object: Some(object.id),
        });
        let mut inside = Vec::new();
        let redirection = object.surface.redirect(&at, &mut |p| inside.push(p));
        (ray, t_min) = match redirection {
            Redirection::Ends => return finish(points, End::Absorbed, ray.direction),
            Redirection::Lost => return finish(points, End::Lost, ray.direction),
            Redirection::Leaves { direction, .. } => at.leaving(direction),
            Redirection::Crosses { exit, .. } => {
                let arrival = if inside.is_empty() {
                    Arrival::Chord
                } else {
                    Arrival::Curved
                };
                points.extend(inside.into_iter().map(|position| Point {
                    position,
                    arrival,
                    object: None,
                }));
                points.push(Point {
                    position: exit.point,
                    arrival,
                    object: Some(object.id),
                });
                at.emerging(exit)
            }
            Redirection::Jumps { exit, .. } => {
                points.push(Point {
                    position: exit.point,
                    arrival: Arrival::Teleported,
                    object: None,
                });
                at.emerging(exit)
            }
        };
    }
    finish(points, End::MaxInteractions, ray.direction)
}

/// How far to draw a ray that meets nothing from `p`: beyond the farthest corner of `bounds`,
/// and at least 1.
fn escape_length(bounds: Option<(DVec3, DVec3)>, p: DVec3) -> f64 {
    bounds
        .map_or(0.0, |(lo, hi)| (p - lo).abs().max((p - hi).abs()).length())
        .max(1.0)
}
