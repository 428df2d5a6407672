//! Dr TIM's defaults are timbre's (issue 37): a shape or a surface named by its `type` alone is
//! the one Dr TIM's GUI makes when asked for a new one. The numbers here are copied from Dr
//! TIM's sources (the class named with each), not from timbre's: `SceneObjectType`'s default
//! scene objects and the editable classes' constructors `(SceneObject parent, Studio studio)`
//! for shapes and for the objects that carry a law (`EditableThinLens`, `EditableGlens`, ...),
//! `SurfacePropertyPanel`'s fields for the other laws. (The devices' are in tests/devices.rs.)

mod common;

use glam::{DVec2, DVec3};
use num_complex::Complex64;
use timbre::geometry::Shape;
use timbre::surfaces::ideal_lenses::Focus;
use timbre::surfaces::lenses::LensLaw;
use timbre::surfaces::metatoys::{Apertures, Blur, ComplexFunction, Pixels, Transmission};
use timbre::surfaces::{Coloured, Field, Surface};

/// `SurfacePropertyPrimitive.DEFAULT_TRANSMISSION_COEFFICIENT`.
const DEFAULT_TRANSMISSION_COEFFICIENT: f64 = 0.96;

/// The one object of a scene with `shape` and `surface`.
fn object(shape: &str, surface: &str) -> timbre::scene::SceneObject {
    let d = common::images::parse(&format!(
        "studio = \"none\"\n[[object]]\nshape = {shape}\nsurface = {surface}\n"
    ));
    d.objects.into_iter().next().unwrap()
}

fn shape(shape: &str) -> Shape {
    object(shape, "{ type = \"matt\", colour = [1, 1, 1] }").shape
}

/// The surface on a sphere (which every law works on).
fn surface(surface: &str) -> Surface {
    object("{ type = \"sphere\" }", surface).surface
}

#[track_caller]
fn bounds(shape: &Shape, lo: [f64; 3], hi: [f64; 3]) {
    let (l, h) = shape.bounds().unwrap();
    let (lo, hi) = (DVec3::from(lo), DVec3::from(hi));
    assert!(
        (l - lo).length() < 1e-9 && (h - hi).length() < 1e-9,
        "{} bounds {l} to {h}, Dr TIM's {lo} to {hi}",
        shape.kind()
    );
}

#[test]
fn shapes_named_by_their_type_alone_are_dr_tims_new_ones() {
    // SPHERE: EditableScaledParametrisedSphere, centre (0, 0, 10), radius 1.
    let Shape::Sphere(s) = shape("{ type = \"sphere\" }") else {
        panic!()
    };
    assert_eq!((s.centre(), s.radius()), (DVec3::new(0.0, 0.0, 10.0), 1.0));
    // PLANE: EditableParametrisedPlane, point (0, 0, 10), normal (0, 0, 1).
    let plane = shape("{ type = \"plane\" }");
    let Shape::Plane(p) = &plane else { panic!() };
    assert_eq!(p.point(), DVec3::new(0.0, 0.0, 10.0));
    assert_eq!(plane.normal(p.point(), 0), DVec3::Z);
    // DISC: EditableScaledParametrisedDisc, centre (0, 0, 10), normal (0, 0, 1), radius 1.
    let disc = shape("{ type = \"disc\" }");
    let Shape::Disc(d) = &disc else { panic!() };
    assert_eq!((d.centre(), d.radius()), (DVec3::new(0.0, 0.0, 10.0), 1.0));
    assert_eq!(disc.normal(d.centre(), 0), DVec3::Z);
    // CYLINDER: EditableParametrisedCylinder, (−1, 0, 10) to (1, 0, 10), radius 1, with caps.
    let Shape::Cylinder(c) = shape("{ type = \"cylinder\" }") else {
        panic!()
    };
    assert_eq!(
        (c.start(), c.end(), c.radius()),
        (DVec3::new(-1.0, 0.0, 10.0), DVec3::new(1.0, 0.0, 10.0), 1.0)
    );
    // RECTANGLE: EditableScaledParametrisedCentredParallelogram, centre (0, 0, 10), width
    // (3, 0, 0), height (0, 2, 0).
    let rectangle = shape("{ type = \"parallelogram\" }");
    bounds(&rectangle, [-1.5, -1.0, 10.0], [1.5, 1.0, 10.0]);
    // CUBOID: Cuboid(parent, studio), centre (0, 0, 10), faces 1 from it along x, y and z.
    bounds(
        &shape("{ type = \"cuboid\" }"),
        [-1.0, -1.0, 9.0],
        [1.0, 1.0, 11.0],
    );
    // EditableTriangularPrism: base (0, 0, 10), (0, 0, 11), (−1, 0, 11), edge (0, 1, 0).
    bounds(
        &shape("{ type = \"triangular-prism\" }"),
        [-1.0, 0.0, 10.0],
        [0.0, 1.0, 11.0],
    );
    // EditablePlatonicSolid: a tetrahedron of radius 1 about (0, 0, 10), a vertex on +z.
    let tetrahedron = shape("{ type = \"platonic-solid\" }");
    let (lo, hi) = tetrahedron.bounds().unwrap();
    assert!((hi.z - 11.0).abs() < 1e-9 && (lo.z - (10.0 - 1.0 / 3.0)).abs() < 1e-9);
    assert!(tetrahedron.is_solid());
    // EditableParametrisedConvexPolygon: the square (±1, ±1, 10), normal (0, 0, 1).
    let square = shape("{ type = \"convex-polygon\" }");
    bounds(&square, [-1.0, -1.0, 10.0], [1.0, 1.0, 10.0]);
    assert_eq!(square.normal(DVec3::new(0.0, 0.0, 10.0), 0), DVec3::Z);
    // CONE: EditableParametrisedCone, apex (0, 0, 10), axis (0, 0, 1), closed, 45°, height 1:
    // a base of radius tan 45° = 1 at z = 11.
    let cone = shape("{ type = \"cone\" }");
    bounds(&cone, [-1.0, -1.0, 10.0], [1.0, 1.0, 11.0]);
    assert!(cone.is_solid());
    // EditableParametrisedParaboloid: vertex (0, 0, 10), w along (0, 1, 0), w = u² + v²
    // (a = b = 1), height 1: the rim u² + v² = 1 at w = 1; no cap.
    let dish = shape("{ type = \"paraboloid\" }");
    bounds(&dish, [-1.0, 0.0, 9.0], [1.0, 1.0, 11.0]);
    assert!(!dish.is_solid(), "Dr TIM's paraboloid has no cap");
    // SPHERICAL_CAP: EditableSphericalCap, cap centre (0, 0, 10), sphere centre (0, 0, 15),
    // aperture radius 1: the rim at z = 15 − √(5² − 1²).
    bounds(
        &shape("{ type = \"spherical-cap\" }"),
        [-1.0, -1.0, 10.0],
        [1.0, 1.0, 15.0 - 24f64.sqrt()],
    );
    // ARROW: from (0, 0, 10) to (1, 0, 10).
    let (lo, hi) = shape("{ type = \"arrow\" }").bounds().unwrap();
    assert!(
        (lo.x, hi.x) == (0.0, 1.0) && lo.z < 10.0 && hi.z > 10.0,
        "{lo} {hi}"
    );
}

#[test]
fn surfaces_named_by_their_type_alone_are_dr_tims_new_ones() {
    let t = DEFAULT_TRANSMISSION_COEFFICIENT;
    // REFLECTIVE: Reflective(DEFAULT_TRANSMISSION_COEFFICIENT, ...).
    let Surface::Mirror(m) = surface("{ type = \"mirror\" }") else {
        panic!()
    };
    assert_eq!(m.reflection_coefficient, t);
    // REFRACTIVE: index ratio 1 (refractiveIndexRatioPanel), DEFAULT_TRANSMISSION_COEFFICIENT.
    let Surface::Refractive(r) = surface("{ type = \"refractive\" }") else {
        panic!()
    };
    assert_eq!((r.index_ratio, r.transmission_coefficient), (1.0, t));
    // TRANSPARENT: transmissionCoefficientPanel, DEFAULT_TRANSMISSION_COEFFICIENT.
    assert_eq!(
        surface("{ type = \"transparent\" }"),
        Surface::Transparent(timbre::surfaces::Transparent {
            transmission_coefficient: t
        })
    );
    // TILED: EditableSurfaceTiling(GREY50_SHINY, WHITE_SHINY, 1, 1).
    let Surface::Chequerboard(c) = surface("{ type = \"chequerboard\" }") else {
        panic!()
    };
    assert_eq!(c.tile_width, 1.0);
    assert_eq!(
        *c.surfaces,
        [0.5, 1.0].map(|g| Surface::Coloured(Coloured::shiny(DVec3::splat(g))))
    );
    // The §3 lenses: SceneObjectType's LUNEBURG_LENS, EATON_LENS, MAXWELL_FISHEYE_LENS and
    // GGRIN_LENS (r = r′ = 1, φ = 0 for a lens of radius 1), all with
    // DEFAULT_TRANSMISSION_COEFFICIENT, refractive-index ratio 1 and no tunnel.
    for kind in [
        "luneburg-lens",
        "eaton-lens",
        "maxwell-fisheye-lens",
        "ggrin-lens",
    ] {
        let Surface::Lens(l) = surface(&format!("{{ type = \"{kind}\" }}")) else {
            panic!()
        };
        assert_eq!(
            (
                l.transmission_coefficient,
                l.index_ratio,
                l.invisible_radius
            ),
            (t, 1.0, 0.0),
            "{kind}"
        );
        if let LensLaw::Ggrin(g) = &l.law {
            assert_eq!((g.r, g.r_prime, g.phi), (1.0, 1.0, 0.0));
        }
    }
    // METRIC_INTERFACE, GENERALISED_CLAS (eta (1, 1)), ROTATING, FLIPPING, PHASE_CONJUGATING,
    // LORENTZ_TRANSFORM_INTERFACE (beta 0), TELEPORTING: DEFAULT_TRANSMISSION_COEFFICIENT;
    // total internal reflection stays lossless.
    let Surface::MetricInterface(mi) = surface("{ type = \"metric-interface\" }") else {
        panic!()
    };
    assert_eq!(
        (mi.transmission_coefficient, mi.reflection_coefficient),
        (t, 1.0)
    );
    let Surface::ConfocalLensletArrays(g) =
        surface("{ type = \"gcla\", a = [0, 0, 1], u = [1, 0, 0] }")
    else {
        panic!()
    };
    assert_eq!(g.eta, DVec2::ONE);
    assert_eq!(
        (g.transmission, g.reflection_coefficient, g.pixels),
        (Transmission::Constant(t), 1.0, None)
    );
    // GCLAsWithApertures's imperfections: apertures as wide as f₁ and centred, square pixels
    // of 2 mm, 564 nm light.
    let Surface::ConfocalLensletArrays(g) = surface(
        "{ type = \"gcla\", a = [0, 0, 1], u = [1, 0, 0], transmission_coefficient_method = \
         \"geometric\", simulate_diffractive_blur = true, simulate_ray_offset = true }",
    ) else {
        panic!()
    };
    assert_eq!(
        g.transmission,
        Transmission::Geometric(Apertures {
            sigma1: DVec2::ONE,
            sigma2: DVec2::ONE,
            alpha1: DVec2::ZERO,
            alpha2: DVec2::ZERO,
        })
    );
    assert_eq!(
        g.pixels,
        Some(Pixels {
            size: DVec2::splat(2e-3),
            lambda: 564e-9,
            blur: Some(Blur::Uniform),
            ray_offset: true,
            sides: None,
        })
    );
    // IDEALISED_DOVE_PRISM_ARRAY: prism 0 at the origin, inverting x, period 0.1.
    let Surface::IdealisedDovePrismArray(a) = surface("{ type = \"idealised-dove-prism-array\" }")
    else {
        panic!()
    };
    assert_eq!(
        (
            a.centre,
            a.inversion_direction,
            a.period,
            a.transmission_coefficient
        ),
        (DVec3::ZERO, DVec3::X, 0.1, t)
    );
    // PHASE_FRONT (a light-ray field): red, 1° of fuzziness, one way.
    let Surface::LightRayField(f) = surface("{ type = \"light-ray-field\" }") else {
        panic!()
    };
    assert_eq!(
        (f.field, f.colour, f.angular_fuzziness, f.bidirectional),
        (Field::PhaseFront, DVec3::X, 1f64.to_radians(), false)
    );
    // VARIABLE_ETA_CLAS: η = 1 at the origin, ∇η = (1, 0, 0).
    let Surface::VariableEtaConfocalLensletArrays(v) =
        surface("{ type = \"variable-eta-confocal-lenslet-arrays\" }")
    else {
        panic!()
    };
    assert_eq!(
        (
            v.inwards_eta_at_p,
            v.point_p,
            v.grad_eta,
            v.transmission_coefficient
        ),
        (1.0, DVec3::ZERO, DVec3::X, t)
    );
    // COMPLEX_REFRACTIVE (Dr TIM's RefractiveComplex): the index ratio 1, no change.
    let Surface::ComplexMetarefraction(c) = surface("{ type = \"refractive-complex\" }") else {
        panic!()
    };
    assert_eq!(
        (c.function, c.transmission_coefficient),
        (ComplexFunction::Multiplication(Complex64::new(1.0, 0.0)), t)
    );
    // PIXELLATION: 1e-4 × 1e-4 pixels, 632.8 nm, blur and ray offset both simulated.
    let Surface::Pixellation(p) = surface("{ type = \"pixellation\" }") else {
        panic!()
    };
    assert_eq!(
        p.pixels,
        Pixels {
            size: DVec2::splat(1e-4),
            lambda: 632.8e-9,
            blur: Some(Blur::SingleSlit),
            ray_offset: true,
            sides: None,
        }
    );
    let Surface::RayRotating(rr) = surface("{ type = \"ray-rotating\" }") else {
        panic!()
    };
    assert_eq!(
        (rr.transmission_coefficient, rr.reflection_coefficient),
        (t, 1.0)
    );
    // ROTATING_IN_PLANE_OF_INCIDENCE: the rotation-angle field's 0°, the default coefficient.
    let Surface::RayRotatingInPlaneOfIncidence(rp) =
        surface("{ type = \"ray-rotating-in-plane-of-incidence\" }")
    else {
        panic!()
    };
    assert_eq!((rp.angle, rp.transmission_coefficient), (0.0, t));
    // DerivativeControlSurface(): D_i0 = D_o0 = the normal, J = 1, not pixellated.
    let Surface::DerivativeControl(dc) = surface("{ type = \"derivative-control\" }") else {
        panic!()
    };
    assert_eq!(
        (dc.jacobian, dc.pixels, dc.transmission_coefficient),
        (glam::DMat2::IDENTITY, None, t)
    );
    assert_eq!(
        dc.directions,
        timbre::surfaces::CentralDirections::Given {
            inside: None,
            outside: None
        }
    );
    let Surface::RayFlipping(rf) = surface("{ type = \"ray-flipping\" }") else {
        panic!()
    };
    assert_eq!((rf.flip_axis_angle, rf.transmission_coefficient), (0.0, t));
    let Surface::PhaseConjugating(pc) = surface("{ type = \"phase-conjugating\" }") else {
        panic!()
    };
    assert_eq!(pc.coefficient, t);
    let Surface::LorentzWindow(lw) = surface("{ type = \"lorentz-window\" }") else {
        panic!()
    };
    assert_eq!((lw.boost.gamma(), lw.transmission_coefficient), (1.0, t));
    // GALILEO_TRANSFORM_INTERFACE: beta (0, 0, 0), DEFAULT_TRANSMISSION_COEFFICIENT (its basis,
    // NORMALSED_LOCAL_OBJECT_BASIS in the GUI, stays global as for every law, see SCENE_FORMAT).
    let Surface::GalileoWindow(gw) = surface("{ type = \"galileo-window\" }") else {
        panic!()
    };
    assert_eq!((gw.beta, gw.transmission_coefficient), (DVec3::ZERO, t));
    // THIN_LENS: EditableThinLens, centre (0, 0, 10), optical axis (0, 0, −1), focal length 1,
    // DEFAULT_TRANSMISSION_COEFFICIENT.
    let Surface::IdealThinLens(l) = surface("{ type = \"ideal-thin-lens\" }") else {
        panic!()
    };
    assert_eq!(
        (
            l.principal_point,
            l.optical_axis,
            l.focal_length,
            l.transmission_coefficient
        ),
        (DVec3::new(0.0, 0.0, 10.0), DVec3::NEG_Z, 1.0, t)
    );
    // GLENS: EditableGlens, centre (0, 0, 5), optical axis (0, 0, 1), focal lengths −2.5 and
    // 2.5, DEFAULT_TRANSMISSION_COEFFICIENT.
    let Surface::Glens(g) = surface("{ type = \"glens\" }") else {
        panic!()
    };
    assert_eq!((g.optical_axis, g.transmission_coefficient), (DVec3::Z, t));
    assert_eq!(
        g.focus,
        Focus::Finite {
            principal_point: DVec3::new(0.0, 0.0, 5.0),
            focal_length_negative: -2.5,
            focal_length_positive: 2.5,
        }
    );
    // LENSLET_ARRAY: EditableRectangularLensletArray, centre (0, 0, 10), spans (1, 0, 0) and
    // (0, 1, 0), focal length 1, periods 0.1 and 0.1, offsets 0,
    // DEFAULT_TRANSMISSION_COEFFICIENT.
    let Surface::IdealThinLensletArray(a) = surface("{ type = \"ideal-thin-lenslet-array\" }")
    else {
        panic!()
    };
    assert_eq!(
        (
            a.centre,
            a.u,
            a.v,
            a.period,
            a.focal_length,
            a.transmission_coefficient
        ),
        (
            DVec3::new(0.0, 0.0, 10.0),
            DVec3::X,
            DVec3::Y,
            DVec2::splat(0.1),
            1.0,
            t
        )
    );
}

/// A shape or law given its keys keeps them: the defaults fill in only what is missing.
#[test]
fn given_keys_override_the_defaults() {
    let Shape::Sphere(s) = shape("{ type = \"sphere\", radius = 2 }") else {
        panic!()
    };
    assert_eq!((s.centre(), s.radius()), (DVec3::new(0.0, 0.0, 10.0), 2.0));
    let Surface::Glens(g) = surface("{ type = \"glens\", focal_length_positive = 4 }") else {
        panic!()
    };
    let Focus::Finite {
        focal_length_negative,
        focal_length_positive,
        ..
    } = g.focus
    else {
        panic!()
    };
    assert_eq!((focal_length_negative, focal_length_positive), (-2.5, 4.0));
    let Surface::Mirror(m) = surface("{ type = \"mirror\", reflection = 1 }") else {
        panic!()
    };
    assert_eq!(m.reflection_coefficient, 1.0);
}
