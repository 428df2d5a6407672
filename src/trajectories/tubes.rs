//! Drawing trajectories: chains of thin capped cylinders, with spheres at the joints.

use super::{Arrival, RayTrajectory, Trajectory};
use crate::geometry::{Cylinder, Shape, Sphere};
use crate::scene::{ReferenceFrame, SceneObject};
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

/// `c` cut into pieces whose lengths double from 64 radii at its start, so that each piece's
/// bounding box is not much larger than the piece: a long thin diagonal cylinder (a ray drawn
/// to the sky) would otherwise have a box most camera rays pass through.
fn pieces(c: &Cylinder, radius: f64) -> Vec<Cylinder> {
    let (start, end) = (c.start(), c.end());
    let length = start.distance(end);
    let mut cuts = vec![0.0];
    let mut next = 64.0 * radius;
    while next < 0.75 * length {
        cuts.push(next);
        next *= 2.0;
    }
    cuts.push(length);
    cuts.windows(2)
        .filter_map(|w| {
            let at = |d: f64| start.lerp(end, d / length);
            Cylinder::new(at(w[0]), at(w[1]), radius).ok()
        })
        .collect()
}
