//! An independent physics check of the relativistic pinhole camera (§2 of the paper): the
//! Penrose–Terrell effect.
//!
//! A sphere photographed by a camera moving at relativistic speed still has a circular outline
//! *on the celestial sphere*: the set of camera-frame directions of its silhouette is a circular
//! cone, displaced and resized by aberration (aberration is a conformal map of the sphere of
//! directions, so it maps circles to circles). On the flat detector that cone projects to a circle
//! only if its axis is the view direction, so the fit is done on the sphere of directions.
//!
//! The silhouette comes from the renderer's object-id AOV (one ray through each pixel centre).
//! Each boundary sample is the midpoint between a pixel centre inside the silhouette and a
//! 4-neighbour outside it, so it lies within half a pixel of the true outline; that quantisation
//! sets the tolerances below. Residual angles are converted to pixels by dividing by the angular
//! rate of change, per pixel, of the fitted quantity across the detector at that point (the
//! local angular pixel pitch normal to the outline).
//!
//! The scene-frame side of the check uses this file's own Eq 4, not timbre's
//! `Camera::to_scene_frame` or `LorentzTransform`.

use glam::{DMat3, DVec3};
use timbre::embree::Device;
use timbre::render::render;
use timbre::scene::{Scene, SceneDescription, file};

const WIDTH: u32 = 400;
const HEIGHT: u32 = 300;

/// Camera velocity, with a large component across the line of sight.
const BETA: DVec3 = DVec3::new(0.8, 0.0, 0.3);
/// The sphere, in the scene frame. Seen from the camera at rest its centre is 79° away from the
/// view direction, far outside the 60° field of view; aberration brings it into the upper-left
/// part of the picture, magnified about 1.9 times in angle (about 105 pixels across).
const CENTRE: DVec3 = DVec3::new(-13.7, 1.4, 2.7);
const RADIUS: f64 = 1.0;

/// Tolerances, in pixels, for samples that lie within 0.5 px of the true outline (see the module
/// comment): measured 0.24 px RMS and 0.51 px maximum for the circle fit, 0.24 px RMS and 0.50 px
/// maximum for the grazing distance. The wrong (Galilean) law gives 5 px RMS and more.
const CIRCLE_RMS_PX: f64 = 0.35;
const CIRCLE_MAX_PX: f64 = 0.7;
const GRAZE_RMS_PX: f64 = 0.35;
const GRAZE_MAX_PX: f64 = 0.6;
/// A law whose outline is this far (RMS, pixels) from any circle clearly fails the circle test.
const WRONG_LAW_MIN_RMS_PX: f64 = 3.0 * CIRCLE_MAX_PX;

/// Eq 4, written out here: the scene-frame direction of a camera-frame backwards-traced ray of
/// direction `d`, for a camera moving with velocity `beta` (c = 1, β ≠ 0).
fn eq4(beta: DVec3, d: DVec3) -> DVec3 {
    let b2 = beta.length_squared();
    let gamma = 1.0 / (1.0 - b2).sqrt();
    d + (gamma - 1.0) * beta.dot(d) / b2 * beta - gamma * d.length() * beta
}

/// The wrong, Galilean, aberration (no γ): d′ = d − β|d|.
fn galilean(beta: DVec3, d: DVec3) -> DVec3 {
    d - d.length() * beta
}

/// The camera-frame direction whose Galilean image is along the unit scene direction `w`.
fn galilean_inverse(beta: DVec3, w: DVec3) -> DVec3 {
    // d = β + s w with |d| = 1 and s > 0, so that d − β|d| = s w.
    let bw = beta.dot(w);
    let s = -bw + (bw * bw + 1.0 - beta.length_squared()).sqrt();
    beta + s * w
}

/// Points of the circle of the unit sphere with unit axis `axis` and angular radius `rho`.
fn circle_points(axis: DVec3, rho: f64, n: usize) -> Vec<DVec3> {
    let e1 = axis.any_orthonormal_vector();
    let e2 = axis.cross(e1);
    (0..n)
        .map(|k| {
            let (s, c) = (std::f64::consts::TAU * k as f64 / n as f64).sin_cos();
            rho.cos() * axis + rho.sin() * (c * e1 + s * e2)
        })
        .collect()
}

fn outer(v: DVec3) -> DMat3 {
    DMat3::from_cols(v * v.x, v * v.y, v * v.z)
}

/// Least-squares circle on the unit sphere through the unit vectors `u`: its unit axis n and
/// angular radius ρ, minimising Σ (angle(n, u) − ρ)². Starts from the plane a·u = 1 through the
/// points, then Gauss–Newton on the angular residuals.
fn fit_circle_on_sphere(u: &[DVec3]) -> (DVec3, f64) {
    let m: DMat3 = u.iter().map(|&p| outer(p)).sum();
    let a = m.inverse() * u.iter().sum::<DVec3>();
    let (mut n, mut rho) = (a.normalize(), (1.0 / a.length()).acos());
    for _ in 0..50 {
        let (e1, e2) = n.any_orthonormal_pair();
        let (mut jtj, mut jtr) = (DMat3::ZERO, DVec3::ZERO);
        for &p in u {
            let theta = n.dot(p).clamp(-1.0, 1.0).acos();
            // d(angle)/d(n + x e1 + y e2) and d/dρ of the residual angle − ρ.
            let j = DVec3::new(-p.dot(e1), -p.dot(e2), 0.0) / theta.sin() - DVec3::Z;
            jtj += outer(j);
            jtr += j * (theta - rho);
        }
        let step = jtj.inverse() * jtr;
        n = (n - step.x * e1 - step.y * e2).normalize();
        rho -= step.z;
        if step.length() < 1e-14 {
            break;
        }
    }
    (n, rho)
}

/// Least-squares (Kåsa) circle through points of the detector: centre and radius in pixels.
fn fit_circle_on_detector(p: &[(f64, f64)]) -> ((f64, f64), f64) {
    let m: DMat3 = p.iter().map(|&(x, y)| outer(DVec3::new(x, y, 1.0))).sum();
    let b: DVec3 = p
        .iter()
        .map(|&(x, y)| -(x * x + y * y) * DVec3::new(x, y, 1.0))
        .sum();
    let s = m.inverse() * b;
    let (cx, cy) = (-0.5 * s.x, -0.5 * s.y);
    ((cx, cy), (cx * cx + cy * cy - s.z).sqrt())
}

/// RMS and maximum magnitude.
fn rms_max(v: &[f64]) -> (f64, f64) {
    let rms = (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
    (rms, v.iter().fold(0.0, |m: f64, x| m.max(x.abs())))
}

/// The rendered silhouette of the sphere.
struct Outline {
    desc: SceneDescription,
    /// Boundary samples in continuous pixel coordinates.
    pixels: Vec<(f64, f64)>,
    /// Their camera-frame unit directions.
    directions: Vec<DVec3>,
}

impl Outline {
    fn render() -> Outline {
        let text = format!(
            r#"
studio = "none"
[render]
width = {WIDTH}
height = {HEIGHT}
[camera]
type = "pinhole"
position = [0, 0, 0]
view_direction = [0, 0, 1]
up = [0, 1, 0]
horizontal_view_angle_deg = 60
beta = [{}, {}, {}]
shutter = "entrance-pupil"
shutter_time = 0
[[light]]
type = "ambient"
colour = [1, 1, 1]
[[object]]
name = "ball"
shape = {{ type = "sphere", centre = [{}, {}, {}], radius = {RADIUS} }}
surface = {{ type = "matt", colour = [1, 1, 1] }}
"#,
            BETA.x, BETA.y, BETA.z, CENTRE.x, CENTRE.y, CENTRE.z
        );
        let mut desc = file::parse(&text, "penrose-terrell.toml").unwrap();
        desc.render.aovs = true;
        desc.render.spp = 1;
        let device = Device::new("").unwrap();
        let scene = Scene::build(&device, &desc).unwrap();
        let image = render(&scene, &desc.camera, &desc.render, &|_| {}).unwrap();
        let aovs = image.aovs.expect("AOVs were asked for");
        let ball = desc.objects.iter().position(|o| o.name == "ball").unwrap() as f32;
        let inside = |x: u32, y: u32| aovs[(y * WIDTH + x) as usize].object == ball;

        let mut pixels = Vec::new();
        let mut area = 0;
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                if inside(x, y) {
                    area += 1;
                    assert!(
                        x > 0 && y > 0 && x + 1 < WIDTH && y + 1 < HEIGHT,
                        "the sphere touches the image border at ({x}, {y})"
                    );
                }
                if x + 1 < WIDTH && inside(x, y) != inside(x + 1, y) {
                    pixels.push((x as f64 + 0.5, y as f64));
                }
                if y + 1 < HEIGHT && inside(x, y) != inside(x, y + 1) {
                    pixels.push((x as f64, y as f64 + 0.5));
                }
            }
        }
        eprintln!(
            "silhouette: {area} pixels, {} boundary samples",
            pixels.len()
        );
        assert!(
            area > 3000,
            "the sphere should appear large, got {area} pixels"
        );
        let mut outline = Outline {
            desc,
            pixels,
            directions: Vec::new(),
        };
        outline.directions = outline
            .pixels
            .iter()
            .map(|&(x, y)| outline.direction(x, y))
            .collect();
        outline
    }

    /// The camera-frame unit direction of the chief ray through continuous pixel (x, y).
    fn direction(&self, x: f64, y: f64) -> DVec3 {
        self.desc
            .camera
            .chief_ray(WIDTH, HEIGHT, x, y)
            .1
            .normalize()
    }

    /// The continuous pixel position of a camera-frame direction (inverse of `direction`).
    fn pixel_of(&self, d: DVec3) -> (f64, f64) {
        let camera = &self.desc.camera;
        let (right, up) = camera.right_up();
        let (_, d00) = camera.chief_ray(WIDTH, HEIGHT, 0.0, 0.0);
        let (_, d10) = camera.chief_ray(WIDTH, HEIGHT, 1.0, 0.0);
        let pitch = (d10 - d00).length();
        let d = d / d.dot(camera.view_direction());
        (
            0.5 * (WIDTH as f64 - 1.0) + d.dot(right) / pitch,
            0.5 * (HEIGHT as f64 - 1.0) - d.dot(up) / pitch,
        )
    }

    /// Signed distances in pixels of the detector `points` from the zero set of `f` (a function
    /// of the camera-frame unit direction): f divided by the length of its detector gradient.
    fn pixel_residuals(&self, points: &[(f64, f64)], f: &dyn Fn(DVec3) -> f64) -> Vec<f64> {
        let h = 0.5;
        let g = |x, y| f(self.direction(x, y));
        points
            .iter()
            .map(|&(x, y)| {
                let gx = (g(x + h, y) - g(x - h, y)) / (2.0 * h);
                let gy = (g(x, y + h) - g(x, y - h)) / (2.0 * h);
                g(x, y) / gx.hypot(gy)
            })
            .collect()
    }

    /// RMS and maximum pixel distance of `points` from the circle (axis, rho) of the directions
    /// `law(d)` (camera-frame directions d mapped by `law`).
    fn circle_residuals(
        &self,
        points: &[(f64, f64)],
        law: &dyn Fn(DVec3) -> DVec3,
        (axis, rho): (DVec3, f64),
    ) -> (f64, f64) {
        rms_max(&self.pixel_residuals(points, &|d| {
            law(d).normalize().dot(axis).clamp(-1.0, 1.0).acos() - rho
        }))
    }

    /// Fits a circle on the sphere to the boundary directions mapped by `law`; returns the circle
    /// and the RMS and maximum pixel residuals.
    fn fit_mapped(&self, law: &dyn Fn(DVec3) -> DVec3) -> ((DVec3, f64), (f64, f64)) {
        let mapped: Vec<DVec3> = self
            .directions
            .iter()
            .map(|&d| law(d).normalize())
            .collect();
        let circle = fit_circle_on_sphere(&mapped);
        (circle, self.circle_residuals(&self.pixels, law, circle))
    }

    /// RMS and maximum pixel residual of the scene-frame rays, from the camera at the origin along
    /// `law(d)`, passing at distance RADIUS from the sphere centre.
    fn grazing_residuals(&self, law: &dyn Fn(DVec3) -> DVec3) -> (f64, f64) {
        rms_max(&self.pixel_residuals(&self.pixels, &|d| {
            let w = law(d).normalize();
            assert!(w.dot(CENTRE) > 0.0, "ray {w} points away from the sphere");
            (CENTRE - CENTRE.dot(w) * w).length() - RADIUS
        }))
    }
}

/// The outline of the sphere at rest: the cone of directions from the camera that touch it.
fn rest_circle() -> (DVec3, f64) {
    (CENTRE.normalize(), (RADIUS / CENTRE.length()).asin())
}

#[test]
fn the_outline_of_a_sphere_is_a_circle_on_the_celestial_sphere() {
    let o = Outline::render();
    let ((axis, rho), (rms, max)) = o.fit_mapped(&|d| d);
    let (axis_x, axis_y) = o.pixel_of(axis);
    eprintln!(
        "camera frame: circle axis {axis:.5} (pixel ({axis_x:.1}, {axis_y:.1})), angular radius \
         {:.4}°; residuals {rms:.3} px RMS, {max:.3} px max",
        rho.to_degrees()
    );
    assert!(
        rms <= CIRCLE_RMS_PX && max <= CIRCLE_MAX_PX,
        "the outline is not a circle of directions: {rms} px RMS, {max} px max"
    );

    // The outline is not trivially circular on the detector (it is off axis, so perspective
    // stretches it): a circle fitted to the pixel positions themselves misses the tolerance by a
    // factor of 4 (measured 1.45 px RMS, 2.43 px max).
    let ((cx, cy), r) = fit_circle_on_detector(&o.pixels);
    let (flat_rms, flat_max) = rms_max(
        &o.pixels
            .iter()
            .map(|&(x, y)| (x - cx).hypot(y - cy) - r)
            .collect::<Vec<_>>(),
    );
    eprintln!(
        "detector: best circle ({cx:.1}, {cy:.1}) radius {r:.1} px; residuals {flat_rms:.3} px \
         RMS, {flat_max:.3} px max"
    );
    assert!(
        flat_rms > 3.0 * CIRCLE_RMS_PX,
        "the outline is nearly circular on the detector ({flat_rms} px RMS), so this test would \
         not distinguish the celestial sphere from the detector plane"
    );

    // Aberration moved and resized the outline: at rest the sphere is 79° off axis, outside the
    // picture, and 1.9 times smaller in angle.
    let (rest_axis, rest_rho) = rest_circle();
    let shift = axis.angle_between(rest_axis).to_degrees();
    eprintln!(
        "at rest: axis {rest_axis:.5}, {:.1}° off the view direction, angular radius {:.4}°; \
         moved by {shift:.2}°, radius × {:.4}",
        rest_axis
            .angle_between(o.desc.camera.view_direction())
            .to_degrees(),
        rest_rho.to_degrees(),
        rho / rest_rho
    );
    assert!(shift > 30.0, "outline moved by only {shift}°");
    assert!(rho / rest_rho > 1.5, "radius × {}", rho / rest_rho);
}

#[test]
fn the_outline_rays_graze_the_sphere_in_the_scene_frame() {
    let o = Outline::render();

    // Premise: with the entrance-pupil shutter at t = 0 a pinhole ray starts at the camera
    // position, the origin of both frames, so the scene-frame ray is (0, eq4(d)).
    let camera = &o.desc.camera;
    for &(x, y) in o.pixels.iter().step_by(17) {
        let ray = camera.ray(WIDTH, HEIGHT, (x, y), [0.0; 2], &|_, _| None);
        let scene_ray = camera.to_scene_frame(&ray);
        assert_eq!((ray.origin, ray.time), (DVec3::ZERO, 0.0));
        assert!(scene_ray.origin.length() < 1e-12, "{}", scene_ray.origin);
    }

    // (c) Each boundary ray, taken into the scene frame with Eq 4, touches the sphere.
    let (rms, max) = o.grazing_residuals(&|d| eq4(BETA, d));
    eprintln!("relativistic grazing distance − radius: {rms:.3} px RMS, {max:.3} px max");
    assert!(
        rms <= GRAZE_RMS_PX && max <= GRAZE_MAX_PX,
        "boundary rays miss the sphere's edge in the scene frame: {rms} px RMS, {max} px max"
    );

    // The predicted camera-frame outline: the scene-frame tangent cone mapped back by the inverse
    // boost (Eq 4 with −β undoes Eq 4 with β). It is exactly a circle (aberration is conformal)...
    let (rest_axis, rest_rho) = rest_circle();
    let predicted: Vec<DVec3> = circle_points(rest_axis, rest_rho, 720)
        .into_iter()
        .map(|w| eq4(-BETA, w).normalize())
        .collect();
    for &w in &circle_points(rest_axis, rest_rho, 7) {
        let back = eq4(BETA, eq4(-BETA, w));
        assert!(back.normalize().distance(w) < 1e-13, "{back} {w}");
    }
    let (p_axis, p_rho) = fit_circle_on_sphere(&predicted);
    let exactness = predicted
        .iter()
        .map(|u| (u.angle_between(p_axis) - p_rho).abs())
        .fold(0.0, f64::max);
    assert!(exactness < 1e-12, "{exactness} rad");
    // ...and the rendered outline lies on it, without any fitting.
    let (rms, max) = o.circle_residuals(&o.pixels, &|d| d, (p_axis, p_rho));
    let ((axis, rho), _) = o.fit_mapped(&|d| d);
    let (cx, cy) = (0.5 * (WIDTH as f64 - 1.0), 0.5 * (HEIGHT as f64 - 1.0));
    let axis_pitch = o
        .direction(cx - 0.5, cy)
        .angle_between(o.direction(cx + 0.5, cy));
    let (ax, ay) = o.pixel_of(axis);
    let local_pitch = o
        .direction(ax - 0.5, ay)
        .angle_between(o.direction(ax + 0.5, ay));
    eprintln!(
        "predicted circle: axis {p_axis:.5}, angular radius {:.4}°; rendered outline off it by \
         {rms:.3} px RMS, {max:.3} px max; fitted axis off by {:.3} px, radius by {:.3} px \
         (pitch {:.5}° on the optical axis, {:.5}° at the outline's centre)",
        p_rho.to_degrees(),
        axis.angle_between(p_axis) / local_pitch,
        (rho - p_rho) / local_pitch,
        axis_pitch.to_degrees(),
        local_pitch.to_degrees()
    );
    assert!(
        rms <= CIRCLE_RMS_PX && max <= CIRCLE_MAX_PX,
        "the outline is not where Eq 4 puts it: {rms} px RMS, {max} px max"
    );
    assert!(axis.angle_between(p_axis) < 0.25 * local_pitch);
    assert!((rho - p_rho).abs() < 0.25 * local_pitch);

    // The Galilean law sends the same boundary rays far past the sphere's edge.
    let (g_rms, g_max) = o.grazing_residuals(&|d| galilean(BETA, d));
    eprintln!("Galilean grazing distance − radius: {g_rms:.1} px RMS, {g_max:.1} px max");
    assert!(g_rms > 10.0 * GRAZE_MAX_PX);
}

#[test]
fn a_galilean_aberration_would_fail_the_circle_test() {
    let o = Outline::render();

    // The relativistic law maps the rendered outline to a circle in the scene frame too (the
    // tangent cone of the sphere)...
    let ((axis, rho), (rms, max)) = o.fit_mapped(&|d| eq4(BETA, d));
    let (rest_axis, rest_rho) = rest_circle();
    eprintln!(
        "Eq 4 of the outline: circle axis {axis:.5}, angular radius {:.4}° (tangent cone \
         {rest_axis:.5}, {:.4}°); residuals {rms:.3} px RMS, {max:.3} px max",
        rho.to_degrees(),
        rest_rho.to_degrees()
    );
    assert!(rms <= CIRCLE_RMS_PX && max <= CIRCLE_MAX_PX);

    // ...but the Galilean law, d′ = d − β|d|, does not map it to any circle: it is not conformal.
    let ((g_axis, g_rho), (g_rms, g_max)) = o.fit_mapped(&|d| galilean(BETA, d));
    eprintln!(
        "Galilean law of the outline: best circle axis {g_axis:.5}, angular radius {:.4}°; \
         residuals {g_rms:.2} px RMS, {g_max:.2} px max",
        g_rho.to_degrees()
    );
    assert!(
        g_rms > WRONG_LAW_MIN_RMS_PX,
        "the Galilean law passes the circle test too ({g_rms} px RMS): the test is vacuous"
    );

    // A renderer using the Galilean law would draw the outline whose Galilean images are the
    // tangent cone; that outline is not a circle of directions in the camera frame.
    let drawn: Vec<DVec3> = circle_points(rest_axis, rest_rho, 360)
        .into_iter()
        .map(|w| galilean_inverse(BETA, w))
        .collect();
    for (&d, w) in drawn.iter().zip(circle_points(rest_axis, rest_rho, 360)) {
        assert!(galilean(BETA, d).normalize().distance(w) < 1e-12);
    }
    // (It lies partly beyond the left edge of the picture; the detector plane is extended.)
    for &d in &drawn {
        assert!(d.dot(o.desc.camera.view_direction()) > 0.3, "{d}");
    }
    let drawn_pixels: Vec<(f64, f64)> = drawn.iter().map(|&d| o.pixel_of(d)).collect();
    let x_max = drawn_pixels
        .iter()
        .map(|p| p.0)
        .fold(f64::NEG_INFINITY, f64::max);
    eprintln!("the Galilean outline would lie left of x = {x_max:.1} px");
    let circle = fit_circle_on_sphere(&drawn);
    let (d_rms, d_max) = o.circle_residuals(&drawn_pixels, &|d| d, circle);
    eprintln!(
        "outline a Galilean camera would draw: best circle angular radius {:.4}°; residuals \
         {d_rms:.2} px RMS, {d_max:.2} px max",
        circle.1.to_degrees()
    );
    assert!(
        d_rms > WRONG_LAW_MIN_RMS_PX,
        "a Galilean camera's outline passes the circle test too ({d_rms} px RMS)"
    );
}
