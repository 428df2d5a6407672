//! TIM's standard studio: sky, chequerboard floor, lights, the default camera and (for
//! "lattice") the cylinder lattice. Lengths are in floor tiles; x right, y up, camera along +z.

use glam::DVec3;

use super::lights::{Lights, PointLight};
use super::{RenderSettings, SceneDescription, SceneObject, SeenBy, Stereo};
use crate::cameras::Camera;
use crate::geometry::{Cylinder, Parallelogram, Plane, Shape, Sphere};
use crate::math::{Colour, ReferenceFrame};
use crate::surfaces::metatoys::RotationAxis;
use crate::surfaces::{Chequerboard, Coloured, RayRotating, Surface};

/// The backdrop a scene starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Studio {
    /// Sky, floor, lights and camera.
    Empty,
    /// The empty studio plus TIM's lattice of 48 red, green and blue cylinders.
    Lattice,
    /// TIM's "METATOY science" scene: a smaller lattice behind a framed window whose surface
    /// is a METATOY (by default ray-rotating by 60°).
    MetatoyWindow,
}

/// Sky: a sphere of radius 100 000 about the origin, constant colour (0.5, 0.5, 1), no shadow.
pub fn sky() -> SceneObject {
    SceneObject {
        name: "sky".into(),
        shape: Shape::Sphere(Sphere::new(DVec3::ZERO, 1e5).expect("valid sky")),
        surface: Surface::ConstantColour(Colour::new(0.5, 0.5, 1.0)),
        shadow_throwing: false,
        frame: ReferenceFrame::Scene,
        seen_by: SeenBy::All,
    }
}

/// Floor: the plane y = −1.0001 with unit chequerboard tiles aligned with x and z; tiles with
/// floor(x) + floor(z) even are 0.8 grey, odd ones white, both shiny.
pub fn floor() -> SceneObject {
    // Surface coordinates (u, v) = (z, x): u along z makes v = w × u = y × z = x.
    let plane = Plane::new(DVec3::new(0.0, -1.0001, 0.0), DVec3::Y, DVec3::Z).expect("valid floor");
    SceneObject {
        name: "floor".into(),
        shape: Shape::Plane(plane),
        surface: Surface::Chequerboard(Chequerboard {
            tile_width: 1.0,
            surfaces: Box::new([
                Surface::Coloured(Coloured::shiny(Colour::splat(0.8))),
                Surface::Coloured(Coloured::shiny(Colour::ONE)),
            ]),
        }),
        shadow_throwing: true,
        frame: ReferenceFrame::Scene,
        seen_by: SeenBy::All,
    }
}

/// Ambient (0.2, 0.2, 0.2) and a white point light at (100, 300, −500), Phong exponent 40.
pub fn lights() -> Lights {
    Lights {
        ambient: Colour::splat(0.2),
        points: vec![PointLight {
            position: DVec3::new(100.0, 300.0, -500.0),
            colour: Colour::ONE,
            phong_exponent: 40.0,
        }],
    }
}

/// Pinhole at the origin looking along +z, up +y, horizontal view angle 20°.
pub const CAMERA_POSITION: DVec3 = DVec3::ZERO;
pub const CAMERA_VIEW_DIRECTION: DVec3 = DVec3::Z;
pub const CAMERA_UP: DVec3 = DVec3::Y;
pub const CAMERA_VIEW_ANGLE_DEG: f64 = 20.0;

pub fn camera() -> Camera {
    Camera::pinhole(
        CAMERA_POSITION,
        CAMERA_VIEW_DIRECTION,
        CAMERA_UP,
        CAMERA_VIEW_ANGLE_DEG.to_radians(),
    )
    .expect("valid camera")
}

/// The 48 cylinders (radius 0.02, shiny, shadow-throwing) of TIM's lattice on the grid
/// x ∈ {−1, −1/3, 1/3, 1}, y ∈ {−0.98, −0.98 + 2/3, −0.98 + 4/3, 1.02}, z ∈ {10, 20, 30, 40}: red along z,
/// blue along x, green along y.
pub fn lattice() -> Vec<SceneObject> {
    let ys = (0..4)
        .map(|i| -0.98 + i as f64 * (1.02 + 0.98) / 3.0)
        .collect::<Vec<_>>();
    cylinder_lattice(
        [-1.0, -1.0 / 3.0, 1.0 / 3.0, 1.0],
        ys.try_into().expect("four"),
        [10.0, 20.0, 30.0, 40.0],
    )
}

/// The lattice behind the METATOY window: x, y ∈ {−0.98, −0.98/3, 0.98/3, 0.98},
/// z ∈ {11, 20, 29, 38}.
pub fn metatoy_lattice() -> Vec<SceneObject> {
    let xy = [-0.98, -0.98 / 3.0, 0.98 / 3.0, 0.98];
    cylinder_lattice(xy, xy, [11.0, 20.0, 29.0, 38.0])
}

/// 48 cylinders of radius 0.02 (shiny, shadow-throwing) through the grid points: red along z,
/// blue along x, green along y, each spanning the grid.
fn cylinder_lattice(xs: [f64; 4], ys: [f64; 4], zs: [f64; 4]) -> Vec<SceneObject> {
    let cylinder = |name: String, start: DVec3, end: DVec3, colour: Colour| SceneObject {
        name,
        shape: Shape::Cylinder(Cylinder::new(start, end, 0.02).expect("valid lattice cylinder")),
        surface: Surface::Coloured(Coloured::shiny(colour)),
        shadow_throwing: true,
        frame: ReferenceFrame::Scene,
        seen_by: SeenBy::All,
    };
    let mut objects = Vec::with_capacity(48);
    for (i, &x) in xs.iter().enumerate() {
        for (j, &y) in ys.iter().enumerate() {
            objects.push(cylinder(
                format!("red cylinder {i},{j}"),
                DVec3::new(x, y, zs[0]),
                DVec3::new(x, y, zs[3]),
                Colour::X,
            ));
        }
    }
    for (j, &y) in ys.iter().enumerate() {
        for (k, &z) in zs.iter().enumerate() {
            objects.push(cylinder(
                format!("blue cylinder {j},{k}"),
                DVec3::new(xs[0], y, z),
                DVec3::new(xs[3], y, z),
                Colour::Z,
            ));
        }
    }
    for (i, &x) in xs.iter().enumerate() {
        for (k, &z) in zs.iter().enumerate() {
            objects.push(cylinder(
                format!("green cylinder {i},{k}"),
                DVec3::new(x, ys[0], z),
                DVec3::new(x, ys[3], z),
                Colour::Y,
            ));
        }
    }
    objects
}

/// Name of the METATOY window's pane.
pub const WINDOW: &str = "window";

/// The METATOY window's pane: corner (−1.5, −0.98, 10), spans (3, 0, 0) and (0, 2, 0), outward
/// normal +z (so the camera sees it from inside); not shadow-throwing.
pub fn window_pane(surface: Surface) -> SceneObject {
    SceneObject {
        name: WINDOW.into(),
        shape: Shape::Parallelogram(
            Parallelogram::new(
                DVec3::new(-1.5, -0.98, 10.0),
                DVec3::X * 3.0,
                DVec3::Y * 2.0,
            )
            .expect("valid window"),
        ),
        surface,
        shadow_throwing: false,
        frame: ReferenceFrame::Scene,
        seen_by: SeenBy::All,
    }
}

/// The window's default surface: TIM's "Rotating" (Dr TIM's 60°, −60° here) about the
/// normal, transmission 0.96.
pub fn default_window_surface() -> Surface {
    Surface::RayRotating(RayRotating {
        angle: RayRotating::DEFAULT_ANGLE_DEG.to_radians(),
        axis: RotationAxis::Normal,
        transmission_coefficient: 0.96,
        reflection_coefficient: 1.0,
    })
}

/// The window's frame: capped cylinders of radius 0.025 along the pane's edges and spheres of
/// radius 0.025 at its corners, shiny grey (diffuse 0.5, specular white), shadow-throwing.
pub fn window_frame() -> Vec<SceneObject> {
    let corners = [
        DVec3::new(-1.5, -0.98, 10.0),
        DVec3::new(1.5, -0.98, 10.0),
        DVec3::new(1.5, 1.02, 10.0),
        DVec3::new(-1.5, 1.02, 10.0),
    ];
    let grey = Surface::Coloured(Coloured {
        diffuse: Colour::splat(0.5),
        specular: Colour::ONE,
    });
    let part = |name: String, shape: Shape| SceneObject {
        name,
        shape,
        surface: grey.clone(),
        shadow_throwing: true,
        frame: ReferenceFrame::Scene,
        seen_by: SeenBy::All,
    };
    (0..4)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % 4]);
            part(
                format!("window frame edge {i}"),
                Shape::Cylinder(Cylinder::new(a, b, 0.025).expect("valid frame edge")),
            )
        })
        .chain((0..4).map(|i| {
            part(
                format!("window frame corner {i}"),
                Shape::Sphere(Sphere::new(corners[i], 0.025).expect("valid frame corner")),
            )
        }))
        .collect()
}

impl Studio {
    /// The studio as a complete scene with TIM's default render settings (640×480, 1 spp).
    pub fn description(self) -> SceneDescription {
        let mut objects = vec![sky(), floor()];
        match self {
            Studio::Empty => {}
            Studio::Lattice => objects.extend(lattice()),
            Studio::MetatoyWindow => {
                objects.extend(metatoy_lattice());
                objects.push(window_pane(default_window_surface()));
                objects.extend(window_frame());
            }
        }
        SceneDescription {
            animation: None,
            objects,
            arrays: Vec::new(),
            lights: lights(),
            camera: camera(),
            focus_surface: Vec::new(),
            stereo: Stereo::default(),
            file_warnings: Vec::new(),
            render: RenderSettings::default(),
            trajectories: Vec::new(),
        }
    }
}
