//! Glass traced by hand: Snell's law written here from a shape's normal, independently of
//! timbre's surface laws, and rays followed with it through a scene's refractive objects.

use glam::DVec3;
use timbre::surfaces::Surface;

/// Snell's law for the unit direction `d` meeting a surface of unit normal `normal` with index
/// `n_inside` behind it (against the normal) and 1 in front, or `None` for total internal
/// reflection: the tangential part of n d is kept, the normal part fills the unit vector.
pub fn snell(d: DVec3, normal: DVec3, n_inside: f64) -> Option<DVec3> {
    let cos = d.dot(normal);
    // From the front (cos < 0) into the glass, or from the glass out.
    let (n1, n2) = if cos < 0.0 {
        (1.0, n_inside)
    } else {
        (n_inside, 1.0)
    };
    let tangential = n1 / n2 * (d - cos * normal);
    let along = 1.0 - tangential.length_squared();
    (along >= 0.0).then(|| tangential + along.sqrt() * cos.signum() * normal)
}

/// A unit vector across `axis`.
pub fn across(axis: DVec3) -> (DVec3, DVec3) {
    let u = axis.any_orthonormal_vector();
    (u, axis.cross(u))
}

/// A ray followed through the objects of `description` with [`snell`] at refractive surfaces:
/// the objects met, and the last point and direction; `None` if it ends on another surface.
pub fn follow(
    description: &timbre::scene::SceneDescription,
    mut o: DVec3,
    mut d: DVec3,
) -> Option<(Vec<String>, DVec3, DVec3)> {
    let mut met = Vec::new();
    for _ in 0..20 {
        let nearest = description
            .objects
            .iter()
            .filter_map(|obj| {
                let (t, part) = obj.shape.intersect(o, d, 1e-9, 1e6)?;
                Some((t, part, obj))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((t, part, obj)) = nearest else {
            return Some((met, o, d));
        };
        let Surface::Refractive(r) = &obj.surface else {
            return None;
        };
        o += t * d;
        d = snell(d, obj.shape.normal(o, part), r.index_ratio)?;
        met.push(obj.name.clone());
    }
    None
}
