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
                objects.push(object(Shape::Cylinder(c.clone())));
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
