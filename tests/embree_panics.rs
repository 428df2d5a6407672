//! A panic in Rust code that Embree calls back (a user geometry's `bounds` or `intersect`)
//! reaches the caller of the Embree call as an ordinary Rust panic with its own message,
//! instead of unwinding into C, which would abort this whole test process.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};

use glam::{DVec3, Vec3};
use timbre::embree::{Bounds, Device, ExactRay, Scene, UserGeometry};

/// One unit box at the origin whose `intersect` hits at its front face (z = −1), or panics for
/// rays going left (−x), and whose `bounds` panics when asked to.
struct Fragile {
    panic_in_bounds: bool,
}

impl UserGeometry for Fragile {
    fn primitive_count(&self) -> u32 {
        1
    }

    fn bounds(&self, _prim: u32) -> Bounds {
        if self.panic_in_bounds {
            panic!("bounds of the fragile box");
        }
        Bounds {
            lower: Vec3::splat(-1.0),
            upper: Vec3::splat(1.0),
        }
    }

    fn intersect(&self, _prim: u32, ray: &ExactRay, t_near: f64, t_far: f64) -> Option<(f64, u32)> {
        if ray.direction.x < 0.0 {
            panic!("intersect with a ray going left, t_far {t_far}");
        }
        let t = (-1.0 - ray.origin.z) / ray.direction.z;
        (t_near < t && t < t_far).then_some((t, 0))
    }
}

fn scene(device: &Device, panic_in_bounds: bool) -> Scene {
    let mut builder = device.scene_builder().expect("scene builder");
    builder
        .add_user(Box::new(Fragile { panic_in_bounds }), 1)
        .expect("user geometry");
    builder.commit().expect("commit")
}

/// A ray from z = −5 along +z towards the box, leaning left for `left`.
fn ray(left: bool) -> ExactRay {
    let x = if left { -0.01 } else { 0.01 };
    ExactRay {
        origin: DVec3::new(0.0, 0.0, -5.0),
        direction: DVec3::new(x, 0.0, 1.0),
    }
}

/// The message of a panic payload (`panic!` with a literal gives a `&str`, else a `String`).
fn message(payload: Box<dyn Any + Send>) -> String {
    match payload.downcast::<String>() {
        Ok(s) => *s,
        Err(payload) => match payload.downcast::<&str>() {
            Ok(s) => s.to_string(),
            Err(_) => panic!("a panic payload that is not a string"),
        },
    }
}

/// The message of the panic `f` raises; fails the test if it returns.
#[track_caller]
fn panic_message<T>(f: impl FnOnce() -> T) -> String {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(_) => panic!("no panic"),
        Err(payload) => message(payload),
    }
}

#[test]
fn a_panic_in_intersect_surfaces_from_every_query() {
    let device = Device::new("").unwrap();
    let scene = scene(&device, false);
    let expected = "intersect with a ray going left, t_far";

    let m = panic_message(|| scene.intersect(&ray(true), 0.0, 100.0, 1));
    assert!(m.starts_with(expected), "{m}");
    let m = panic_message(|| scene.occluded(&ray(true), 0.0, 100.0, 1));
    assert!(m.starts_with(expected), "{m}");
    // In a packet, one panicking lane is enough.
    let m = panic_message(|| scene.intersect8(&[ray(false), ray(true), ray(false)], 0.0, 100.0, 1));
    assert!(m.starts_with(expected), "{m}");

    // The scene is still usable, and no panic is left over for the next query.
    let hit = scene.intersect(&ray(false), 0.0, 100.0, 1).expect("a hit");
    assert!(hit.exact && (hit.t - 4.0).abs() < 1e-12, "{hit:?}");
    assert!(scene.occluded(&ray(false), 0.0, 100.0, 1));
    assert!(
        scene
            .intersect8(&[ray(false); 8], 0.0, 100.0, 1)
            .iter()
            .all(Option::is_some)
    );
}

#[test]
fn a_panic_in_intersect_inside_an_instance_surfaces() {
    let device = Device::new("").unwrap();
    let inner = std::sync::Arc::new(scene(&device, false));
    let mut builder = device.scene_builder().unwrap();
    builder
        .add_instance(inner, DVec3::new(0.0, 0.0, 2.0), 1)
        .unwrap();
    let outer = builder.commit().unwrap();
    let m = panic_message(|| outer.intersect(&ray(true), 0.0, 100.0, 1));
    assert!(m.starts_with("intersect with a ray going left"), "{m}");
    let hit = outer.intersect(&ray(false), 0.0, 100.0, 1).expect("a hit");
    assert!((hit.t - 6.0).abs() < 1e-12, "{hit:?}");
}

#[test]
fn a_panic_in_bounds_surfaces_from_commit() {
    let device = Device::new("").unwrap();
    let m = panic_message(|| scene(&device, true));
    assert_eq!(m, "bounds of the fragile box");
    // The device is still usable.
    let scene = scene(&device, false);
    assert!(scene.intersect(&ray(false), 0.0, 100.0, 1).is_some());
}
