//! Following rays forwards through a scene, recording where they meet surfaces.

use glam::DVec3;

use super::{Arrival, End, MAX_CURVED_POINTS, MAX_POINTS, Point, Trajectory, TrajectoryError};
use crate::embree::Device;
use crate::geometry::Interaction;
use crate::math::{Colour, Ray, ReferenceFrame};
use crate::scene::{SceneDescription, SeenBy, World};
use crate::surfaces::{Redirection, Weighted};

/// Follows every ray of every trajectory source of `description` through its scene-frame
/// objects, in order of the sources and their rays. All of them together may have at most
/// [`MAX_POINTS`] points.
pub fn trace(
    device: &Device,
    description: &SceneDescription,
) -> Result<Vec<Trajectory>, TrajectoryError> {
    let world = World::build(
        device,
        description,
        ReferenceFrame::Scene,
        SeenBy::Trajectories,
    )?;
    let bounds = description.summary().bounds;
    let mut budget = MAX_POINTS;
    let mut traced = Vec::new();
    for (s, source) in description.trajectories.iter().enumerate() {
        for (k, ray) in source.rays().into_iter().enumerate() {
            let mut t = follow(&world, ray, source.max_interactions, bounds);
            budget = budget.checked_sub(t.points.len()).ok_or_else(|| {
                TrajectoryError::TooManyPoints {
                    trajectory: source.name.clone(),
                }
            })?;
            (t.source, t.ray) = (s, k);
            traced.push(t);
        }
    }
    Ok(traced)
}

/// The path of `ray` through `world` (its source and index set to 0), until it is absorbed or
/// lost, meets nothing more, or has met `max_interactions` surfaces. Every surface applies its
/// law exactly as the renderer does to a ray arriving the same way; for the reciprocal laws
/// that is the path light takes. A law that passes on none of the light (a coefficient of 0)
/// loses the ray.
///
/// A ray that meets nothing is drawn on to beyond the farthest corner of `bounds` (the bounding
/// box of the scene's bounded objects) from its last point, and at least a distance of 1.
fn follow(
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
    for _ in 0..max_interactions {
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
        let at = world.geometry.interaction(ray, hit);
        points.push(Point {
            position: at.point(),
            arrival: Arrival::Straight,
            object: Some(object.id),
        });
        let mut inside = Thinned::default();
        let redirection = object.surface.redirect(&at, &mut |p| inside.push(p));
        let redirection = strongest(redirection, &at, &mut |p| inside.push(p));
        (ray, t_min) = match redirection {
            // (A mix is never left by `strongest`.)
            Redirection::Lit(_) | Redirection::Emits(_) | Redirection::Mixes(_) => {
                return finish(points, End::Absorbed, ray.direction);
            }
            Redirection::Lost => return finish(points, End::Lost, ray.direction),
            Redirection::Leaves { factor, .. }
            | Redirection::Crosses { factor, .. }
            | Redirection::Jumps { factor, .. }
                if factor == Colour::ZERO =>
            {
                return finish(points, End::Lost, ray.direction);
            }
            Redirection::Leaves { direction, .. } => at.leaving(direction),
            Redirection::Absorbs { direction, .. } => at.leaving(direction),
            Redirection::Glows { .. } => at.leaving(ray.direction),
            Redirection::Crosses { exit, .. } => {
                let inside = inside.points;
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

/// The one way on a trajectory takes from a redirection: of a mixed surface's parts, the one
/// that passes on the most light (the greatest sum of its weight's channels) of those that send
/// the ray on; the first part if none does (a semi-transparent surface's trajectory goes
/// through it, an opaque mix absorbs it).
fn strongest<'a>(
    redirection: Redirection<'a>,
    at: &Interaction,
    inside: &mut dyn FnMut(DVec3),
) -> Redirection<'a> {
    let Redirection::Mixes(parts) = redirection else {
        return redirection;
    };
    let goes_on = |r: &Redirection| match r {
        Redirection::Leaves { factor, .. }
        | Redirection::Crosses { factor, .. }
        | Redirection::Jumps { factor, .. } => *factor != Colour::ZERO,
        Redirection::Absorbs { .. } | Redirection::Glows { .. } => true,
        Redirection::Lit(_) | Redirection::Emits(_) | Redirection::Lost | Redirection::Mixes(_) => {
            false
        }
    };
    let weight = |w: &Weighted| w.weight.element_sum();
    let mut best: Option<&Weighted> = None;
    for part in parts {
        let r = strongest(part.surface.redirect(at, &mut |_| {}), at, &mut |_| {});
        if goes_on(&r) && best.is_none_or(|b| weight(part) > weight(b)) {
            best = Some(part);
        }
    }
    // The chosen part is redirected again to show its path inside.
    best.or(parts.first()).map_or(Redirection::Lost, |part| {
        strongest(part.surface.redirect(at, inside), at, inside)
    })
}

/// The points of a curved path, evenly thinned to at most [`MAX_CURVED_POINTS`]: every
/// `stride`th point shown is kept, and when the list fills, every other one is dropped and the
/// stride doubles.
struct Thinned {
    points: Vec<DVec3>,
    stride: usize,
    shown: usize,
}

impl Default for Thinned {
    fn default() -> Thinned {
        Thinned {
            points: Vec::new(),
            stride: 1,
            shown: 0,
        }
    }
}

impl Thinned {
    fn push(&mut self, p: DVec3) {
        if self.shown.is_multiple_of(self.stride) {
            self.points.push(p);
            if self.points.len() == MAX_CURVED_POINTS {
                let mut k = 0;
                self.points.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                self.stride *= 2;
            }
        }
        self.shown += 1;
    }
}

/// How far to draw a ray that meets nothing from `p`: beyond the farthest corner of `bounds`,
/// and at least 1.
fn escape_length(bounds: Option<(DVec3, DVec3)>, p: DVec3) -> f64 {
    bounds
        .map_or(0.0, |(lo, hi)| (p - lo).abs().max((p - hi).abs()).length())
        .max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_curved_paths_are_thinned_evenly_in_order() {
        for shown in [10, 255, 256, 1000, 100_000] {
            let mut path = Thinned::default();
            for k in 0..shown {
                path.push(DVec3::new(k as f64, 0.0, 0.0));
            }
            let kept: Vec<f64> = path.points.iter().map(|p| p.x).collect();
            assert!(kept.len() < MAX_CURVED_POINTS, "{shown}: {}", kept.len());
            assert!(kept.len() >= (MAX_CURVED_POINTS / 2).min(shown), "{shown}");
            assert_eq!(kept[0], 0.0);
            let stride = kept.get(1).map_or(1.0, |x| x - kept[0]);
            assert!(
                kept.windows(2).all(|w| w[1] - w[0] == stride),
                "{shown}: uneven {kept:?}"
            );
            assert!(
                shown as f64 - kept.last().unwrap() <= stride,
                "{shown}: tail"
            );
        }
    }
}
