//! Drawing trajectories: chains of thin capped cylinders, with spheres at the joints.

use super::{Arrival, Trajectory};
use crate::geometry::{Cylinder, Shape, Sphere};
use crate::math::ReferenceFrame;
use crate::scene::{RayTrajectory, SceneObject, SeenBy};
use crate::surfaces::Surface;

/// The objects that draw `trajectories` (traced from `sources`): a cylinder of the source's
/// radius and colour between consecutive points (none into a teleported point, none between
/// coincident points) and, if the source asks for them, a sphere of the same radius at every
/// point between two cylinders. They emit their colour whatever the lighting, cast no shadows,
/// and are at rest in the scene frame; each is named after its source.
pub fn tubes(sources: &[RayTrajectory], trajectories: &[Trajectory]) -> Vec<SceneObject> {
    let mut objects = Vec::new();
    for t in trajectories {
        let source = &sources[t.source];
        let object = |shape| SceneObject {
            name: source.name.clone(),
            shape,
            surface: Surface::ConstantColour(source.colour),
            shadow_throwing: false,
            frame: ReferenceFrame::Scene,
            seen_by: SeenBy::All,
        };
        let segments: Vec<Option<Cylinder>> = t
            .points
            .windows(2)
            .map(|w| match w[1].arrival {
                Arrival::Teleported => None,
                _ => Cylinder::new(w[0].position, w[1].position, source.radius).ok(),
            })
            .collect();
        for (k, segment) in segments.iter().enumerate() {
            if let Some(c) = segment {
                let pieces = pieces(c, source.radius);
                objects.extend(pieces.into_iter().map(|p| object(Shape::Cylinder(p))));
            }
            let joint = segment.is_some() && segments.get(k + 1).is_some_and(Option::is_some);
            if source.joints && joint {
                let centre = t.points[k + 1].position;
                if let Ok(s) = Sphere::new(centre, source.radius) {
                    objects.push(object(Shape::Sphere(s)));
                }
            }
        }
    }
    objects
}

/// `c` cut into pieces whose lengths double from each end towards the middle, starting at 64
/// radii (or 2⁻²⁰ of the length, so there are at most 41 pieces), so that each piece's bounding
/// box is not much larger than the piece: a long thin diagonal cylinder (a ray drawn to the
/// sky) would otherwise have a box that most camera rays pass through.
fn pieces(c: &Cylinder, radius: f64) -> Vec<Cylinder> {
    let (start, end) = (c.start(), c.end());
    let length = start.distance(end);
    let mut from_start = Vec::new();
    let mut next = (64.0 * radius).max(length / 1048576.0);
    while next < 0.5 * length {
        from_start.push(next);
        next *= 2.0;
    }
    let cuts: Vec<f64> = std::iter::once(0.0)
        .chain(from_start.iter().copied())
        .chain(from_start.iter().rev().map(|d| length - d))
        .chain(std::iter::once(length))
        .collect();
    let at = |d: f64| start.lerp(end, d / length);
    cuts.windows(2)
        .filter_map(|w| Cylinder::new(at(w[0]), at(w[1]), radius).ok())
        .collect()
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::math::Colour;
    use crate::scene::Spread;
    use crate::trajectories::End;
    use crate::trajectories::Point;

    fn source(joints: bool) -> RayTrajectory {
        RayTrajectory {
            name: "t".into(),
            start: DVec3::ZERO,
            direction: DVec3::Z,
            spread: Spread::Single,
            radius: 0.01,
            colour: Colour::Y,
            max_interactions: 10,
            joints,
        }
    }

    /// Points at `positions`, arriving as `arrivals` say (the first is the start).
    fn path(positions: &[DVec3], arrivals: &[Arrival]) -> Trajectory {
        Trajectory {
            source: 0,
            ray: 0,
            points: positions
                .iter()
                .zip(arrivals)
                .map(|(&position, &arrival)| Point {
                    position,
                    arrival,
                    object: None,
                })
                .collect(),
            end: End::Absorbed,
            direction: DVec3::Z,
        }
    }

    fn shapes(objects: &[SceneObject]) -> (Vec<Cylinder>, Vec<Sphere>) {
        let mut cylinders = Vec::new();
        let mut spheres = Vec::new();
        for o in objects {
            assert_eq!(o.surface, Surface::ConstantColour(Colour::Y));
            assert!(!o.shadow_throwing);
            match &o.shape {
                Shape::Cylinder(c) => cylinders.push(c.clone()),
                Shape::Sphere(s) => spheres.push(s.clone()),
                s => panic!("unexpected {s:?}"),
            }
        }
        (cylinders, spheres)
    }

    #[test]
    fn a_bent_path_is_two_cylinders_with_a_sphere_at_the_joint() {
        let corner = DVec3::new(0.0, 0.0, 0.5);
        let t = path(
            &[DVec3::ZERO, corner, DVec3::new(0.5, 0.0, 0.5)],
            &[Arrival::Start, Arrival::Straight, Arrival::Straight],
        );
        let (cylinders, spheres) = shapes(&tubes(&[source(true)], std::slice::from_ref(&t)));
        assert_eq!(cylinders.len(), 2);
        assert_eq!(
            (cylinders[0].start(), cylinders[0].end()),
            (DVec3::ZERO, corner)
        );
        assert_eq!(spheres.len(), 1);
        assert_eq!((spheres[0].centre(), spheres[0].radius()), (corner, 0.01));
        let (_, spheres) = shapes(&tubes(&[source(false)], &[t]));
        assert!(spheres.is_empty(), "joints = false");
    }

    #[test]
    fn nothing_is_drawn_into_a_teleported_point() {
        let t = path(
            &[
                DVec3::ZERO,
                DVec3::Z * 0.5,
                DVec3::new(5.0, 0.0, 0.0),
                DVec3::X * 5.5,
            ],
            &[
                Arrival::Start,
                Arrival::Straight,
                Arrival::Teleported,
                Arrival::Straight,
            ],
        );
        let (cylinders, spheres) = shapes(&tubes(&[source(true)], &[t]));
        assert_eq!(cylinders.len(), 2, "before and after the jump only");
        assert!(spheres.is_empty(), "no joint at either end of the jump");
    }

    #[test]
    fn long_segments_are_cut_into_doubling_pieces_end_to_end() {
        let end = DVec3::new(1e4, 0.0, 1e4);
        let c = Cylinder::new(DVec3::ZERO, end, 0.01).unwrap();
        let p = pieces(&c, 0.01);
        assert!(p.len() > 20 && p.len() <= 41, "{} pieces", p.len());
        assert_eq!(p[0].start(), DVec3::ZERO);
        assert!(p.last().unwrap().end().distance(end) < 1e-9);
        for w in p.windows(2) {
            assert_eq!(w[0].end(), w[1].start());
        }
        let length = |c: &Cylinder| c.start().distance(c.end());
        let (first, last) = (length(&p[0]), length(p.last().unwrap()));
        assert!(
            (first - last).abs() < 1e-9 && (first - 0.64).abs() < 1e-12,
            "{first}"
        );
        let thin = Cylinder::new(DVec3::ZERO, end, 1e-300).unwrap();
        assert!(pieces(&thin, 1e-300).len() <= 41);
        let short = Cylinder::new(DVec3::ZERO, DVec3::Z * 0.5, 0.01).unwrap();
        assert_eq!(pieces(&short, 0.01).len(), 1);
    }
}
