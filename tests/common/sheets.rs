//! A law's sheet read from scene text, and what it does with single rays: for the tests of
//! surface laws through `Surface::redirect`.

use glam::DVec3;
use timbre::geometry::{Interaction, Shape};
use timbre::math::Ray;
use timbre::surfaces::{Redirection, Surface};

/// The sheet: the plane z = 0, normal +z, u = x.
pub const PLANE: &str =
    "{ type = \"plane\", point = [0, 0, 0], normal = [0, 0, 1], u_direction = [1, 0, 0] }";

pub fn sheet(surface: &str) -> (Shape, Surface) {
    let d = super::images::parse(&format!(
        "studio = \"none\"\n[[object]]\nshape = {PLANE}\nsurface = {surface}\n"
    ));
    let o = d.objects.into_iter().next().unwrap();
    (o.shape, o.surface)
}

/// What the sheet does with the ray of direction `d` that meets it at (x, y, 0).
pub fn redirect(sheet: &(Shape, Surface), x: f64, y: f64, d: DVec3) -> Redirection<'static> {
    let (shape, surface) = sheet;
    let d = d.normalize();
    let origin = DVec3::new(x, y, 0.0) - d;
    let (t, prim) = shape
        .intersect(origin, d, 0.0, f64::INFINITY)
        .expect("the ray meets the sheet");
    let at = Interaction::on(shape, Ray::new(origin, d, 0.0), t, prim);
    match surface.redirect(&at, &mut |_| {}) {
        Redirection::Leaves { direction, factor } => Redirection::Leaves { direction, factor },
        Redirection::Jumps { exit, factor } => Redirection::Jumps { exit, factor },
        Redirection::Lost => Redirection::Lost,
        other => panic!("unexpected {other:?}"),
    }
}

/// The direction and grey factor of a ray that leaves the hit point.
pub fn leaves(r: Redirection) -> (DVec3, f64) {
    match r {
        Redirection::Leaves { direction, factor } => (direction, factor.x),
        other => panic!("expected the ray to leave the hit point, got {other:?}"),
    }
}
