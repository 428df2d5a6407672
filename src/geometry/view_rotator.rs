//! The glass of a refractive view rotator (Dr TIM's `RefractiveViewRotator`, whose bounding
//! box's surface `SurfaceOfRefractiveViewRotator` builds one refractive wedge per pixel), traced
//! exactly as one solid.
//!
//! **The pixels.** The ocular plane passes through its centre O and is spanned by the periods
//! p₁, p₂; pixel (i, j) is centred on Cᵢⱼ = O + i p₁ + j p₂. Its voxel is the part of space seen
//! from the eye E through the pixel (Dr TIM's two `FanOfPlanes` through E): a point x is in
//! pixel (i, j) when its central projection from E onto the ocular plane,
//! x′ = E + (x − E) k/((x − E)·n̂) with n̂ the plane's unit normal pointing away from E and
//! k = (O − E)·n̂ > 0, has lattice coordinates s = (x′ − O)·p₁*, t = (x′ − O)·p₂* (p₁*, p₂* the
//! reciprocal vectors in the plane) within ½ of i and j. The walls between pixels are planes
//! through E; s and t are linear-fractional along a ray and monotonic wherever
//! (x − E)·n̂ > 0, so the bounding box must lie wholly beyond the plane through E parallel to
//! the ocular plane.
//!
//! **A wedge.** With d_O = (Cᵢⱼ − E)/|Cᵢⱼ − E| the direction from the eye through the pixel's
//! centre, the wedge's ocular face is the plane normal to d_O through C = Cᵢⱼ + D d_O (D the
//! derivative-control thickness, 0 unless room is left for Dr TIM's derivative control) and its
//! objective face passes through Q = C + T d_O (T the wedge thickness). The ray E + μ d_R, d_R
//! being d_O rotated by θ about the rotation axis â with its part across â divided by the
//! magnification M, meets the view plane at X; the objective face's normal
//! n_obj = n d_O − d_obj, d_obj = (X − Q)/|X − Q|, is the one that refracts d_O (inside glass
//! of index n) into d_obj (outside), so that the eye sees X, seen from E, in the direction d_O
//! (Snell's law in vector form: n d_O − d_obj is normal to the surface). The glass is the
//! intersection of the half-spaces (x − C)·d_O ≥ 0 and (x − Q)·n_obj ≤ 0 (n_obj oriented
//! along d_obj), cut to the pixel's voxel and the bounding box. A pixel whose rotated ray misses
//! the view plane has no glass (Dr TIM reports it and leaves the pixel empty).
//!
//! **The solid.** The wedges of neighbouring pixels meet at their common wall without a
//! surface where both are glass, and the wall bounds the glass where only one is; so does the
//! box. A ray walks the voxels ([`super::cell_walk`]), meeting each wedge's two faces.

use glam::{DMat3, DVec2, DVec3};

use super::cell_walk::{Bound, CellSolid, LineCoordinate, clip, walk};
use super::{AnalyticShape, GeometryError, check_direction, check_point, point_bounds};
use crate::math::Frame;

/// The parameters of a refractive view rotator, as Dr TIM's `RefractiveViewRotator` takes
/// them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewRotatorSpec {
    /// The bounding box: its centre and three span vectors (a parallelepiped).
    pub bounding_box_centre: DVec3,
    pub bounding_box_span_vectors: [DVec3; 3],
    /// E.
    pub eye_position: DVec3,
    /// O.
    pub ocular_plane_centre: DVec3,
    /// p₁, p₂.
    pub period_vector_1: DVec3,
    pub period_vector_2: DVec3,
    /// θ, in degrees, about â (right-handed).
    pub rotation_angle_deg: f64,
    pub rotation_axis_direction: DVec3,
    /// M ≠ 0.
    pub magnification_factor: f64,
    /// The view object: the plane through this point with this normal.
    pub view_plane_point: DVec3,
    pub view_plane_normal: DVec3,
    /// n, T ≥ 0.
    pub refractive_index: f64,
    pub wedge_thickness: f64,
    /// D: how far along d_O behind the pixel's centre the wedge starts (Dr TIM's
    /// `derivativeControlThickness`, room for its derivative-control surfaces).
    pub derivative_control_thickness: f64,
}

/// The most pixels a rotator may have (each hit names its pixel in 28 bits).
const MAX_PIXELS: i64 = 1 << 28;

/// The parts a hit can be on, in the low 4 bits of the part number (the pixel's index above
/// them): the ocular or the objective face of the pixel's wedge; a wall across s or t whose
/// outward normal points towards larger (bit 0 clear) or smaller s or t, the wall being the
/// pixel's upper one (between i and i + 1, or j and j + 1); a face of the box (6 + 2k) whose
/// outward normal is +b_k* or −b_k*.
const OCULAR: u32 = 0;
const OBJECTIVE: u32 = 1;
const WALL_S: u32 = 2;
const WALL_T: u32 = 4;
const FACE: u32 = 6;

#[derive(Debug, Clone, PartialEq)]
pub struct ViewRotator {
    centre: DVec3,
    spans: [DVec3; 3],
    /// Reciprocal vectors of the box's spans: x = centre + Σ a_k span_k, a_k = (x − centre)·b_k*.
    span_stars: [DVec3; 3],
    eye: DVec3,
    origin: DVec3,
    p1: DVec3,
    p2: DVec3,
    /// n̂ (away from the eye), p₁*, p₂*, k = (O − E)·n̂ and (s, t) of E's foot on the plane.
    normal: DVec3,
    p1_star: DVec3,
    p2_star: DVec3,
    k: f64,
    eye_st: DVec2,
    /// d ↦ d_R: the rotation followed by the division of the part across â by M.
    rotate_and_magnify: DMat3,
    view_point: DVec3,
    view_normal: DVec3,
    index: f64,
    thickness: f64,
    offset: f64,
    /// The first pixel's indices and the number of pixels along p₂.
    i0: i64,
    j0: i64,
    ni: i64,
    nj: i64,
}

/// Pixel (i, j)'s wedge: a point on and the inward normal d_O of its ocular face, a point on
/// and the outward normal of its objective face; `None` without glass.
pub(super) type Wedge = Option<(DVec3, DVec3, DVec3, DVec3)>;

impl ViewRotator {
    pub fn new(spec: &ViewRotatorSpec) -> Result<ViewRotator, GeometryError> {
        let bad = |why: String| Err(GeometryError::Degenerate(why));
        for (what, p) in [
            ("bounding_box_centre", spec.bounding_box_centre),
            ("eye_position", spec.eye_position),
            ("ocular_plane_centre", spec.ocular_plane_centre),
            ("view_plane_point", spec.view_plane_point),
        ] {
            check_point(what, p)?;
        }
        let spans = spec.bounding_box_span_vectors;
        for span in spans {
            check_direction("bounding_box_span_vectors", span)?;
        }
        let volume = spans[0].dot(spans[1].cross(spans[2]));
        if volume.abs() < 1e-9 * spans[0].length() * spans[1].length() * spans[2].length() {
            return bad("the bounding box's span vectors are (nearly) coplanar".into());
        }
        let span_stars = [
            spans[1].cross(spans[2]) / volume,
            spans[2].cross(spans[0]) / volume,
            spans[0].cross(spans[1]) / volume,
        ];
        let (p1, p2) = (spec.period_vector_1, spec.period_vector_2);
        check_direction("period_vector_1", p1)?;
        check_direction("period_vector_2", p2)?;
        let across = p1.cross(p2);
        if across.length() < 1e-9 * p1.length() * p2.length() {
            return bad("the period vectors are (nearly) parallel".into());
        }
        let (eye, origin) = (spec.eye_position, spec.ocular_plane_centre);
        let mut normal = across.normalize();
        let mut k = (origin - eye).dot(normal);
        if k < 0.0 {
            (normal, k) = (-normal, -k);
        }
        if k <= 1e-9 * (origin - eye).length() || !k.is_normal() {
            return bad(
                "the eye lies in the ocular plane (spanned by the periods through \
                 ocular_plane_centre)"
                    .into(),
            );
        }
        // Every point of the box must lie beyond the plane through the eye parallel to the
        // ocular plane, where each voxel is a single cone from the eye.
        let corners = box_corners(spec.bounding_box_centre, spans);
        let nearest = corners
            .iter()
            .map(|c| (*c - eye).dot(normal))
            .fold(f64::INFINITY, f64::min);
        if nearest <= 1e-6 * k {
            return bad(format!(
                "the bounding box reaches {} behind the plane through the eye parallel to the \
                 ocular plane; it must lie wholly on the ocular plane's side of it",
                -nearest
            ));
        }
        let axis = check_direction("rotation_axis_direction", spec.rotation_axis_direction)?;
        let view_normal = check_direction("view_plane_normal", spec.view_plane_normal)?;
        let m = spec.magnification_factor;
        if m == 0.0 || !m.is_finite() {
            return bad(format!(
                "magnification_factor must be non-zero and finite (it is {m})"
            ));
        }
        let rotation = DMat3::from_axis_angle(axis, spec.rotation_angle_deg.to_radians());
        let along = DMat3::from_cols(axis * axis.x, axis * axis.y, axis * axis.z);
        let rotate_and_magnify = (along + (DMat3::IDENTITY - along) * (1.0 / m)) * rotation;
        let p1_star = p2.cross(normal) / p1.dot(p2.cross(normal));
        let p2_star = normal.cross(p1) / p2.dot(normal.cross(p1));
        let eye_foot = eye + k * normal - origin;
        let mut rotator = ViewRotator {
            centre: spec.bounding_box_centre,
            spans,
            span_stars,
            eye,
            origin,
            p1,
            p2,
            normal,
            p1_star,
            p2_star,
            k,
            eye_st: DVec2::new(eye_foot.dot(p1_star), eye_foot.dot(p2_star)),
            rotate_and_magnify,
            view_point: spec.view_plane_point,
            view_normal,
            index: spec.refractive_index,
            thickness: spec.wedge_thickness,
            offset: spec.derivative_control_thickness,
            i0: 0,
            j0: 0,
            ni: 0,
            nj: 0,
        };
        // The voxels the box reaches into (s and t are extreme at its corners, their level
        // sets being planes), with one more on each side for the walls' part numbers.
        let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
        for corner in corners {
            let st = rotator.st(corner);
            (lo, hi) = (lo.min(st), hi.max(st));
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return bad("the bounding box is too large for its pixels".into());
        }
        let cells = |a: f64, b: f64| ((a + 0.5).floor() - 1.0, (b - 0.5).ceil() + 1.0);
        let ((i0, i1), (j0, j1)) = (cells(lo.x, hi.x), cells(lo.y, hi.y));
        let (ni, nj) = (i1 - i0 + 1.0, j1 - j0 + 1.0);
        if ni * nj > MAX_PIXELS as f64 {
            return bad(format!(
                "the bounding box covers about {:.3e} pixels ({ni} × {nj}), more than \
                 {MAX_PIXELS}",
                ni * nj
            ));
        }
        (rotator.i0, rotator.j0, rotator.ni, rotator.nj) =
            (i0 as i64, j0 as i64, ni as i64, nj as i64);
        Ok(rotator)
    }

    /// The lattice coordinates (s, t) of x's projection from the eye.
    fn st(&self, x: DVec3) -> DVec2 {
        let w = x - self.eye;
        let scale = self.k / w.dot(self.normal);
        self.eye_st + scale * DVec2::new(w.dot(self.p1_star), w.dot(self.p2_star))
    }

    /// The lattice coordinate along p₁* (`star`) of the line origin + λ direction, whose foot
    /// coordinate is `at_eye`: s = s_E + k (w·p*)/(w·n̂), w = origin − E + λ direction.
    fn line_coordinate(
        &self,
        w: DVec3,
        direction: DVec3,
        star: DVec3,
        at_eye: f64,
    ) -> LineCoordinate {
        let (g, d) = (w.dot(self.normal), direction.dot(self.normal));
        LineCoordinate::fractional(
            at_eye * g + self.k * w.dot(star),
            at_eye * d + self.k * direction.dot(star),
            g,
            d,
        )
    }

    /// The wall between pixels c and c + 1 across s (`axis` 0) or t (1), with its normal
    /// pointing towards larger s or t: the plane through E normal to k p* − (c + ½ − s_E) n̂.
    fn wall_normal(&self, axis: usize, c: i64) -> DVec3 {
        let (star, at_eye) = match axis {
            0 => (self.p1_star, self.eye_st.x),
            _ => (self.p2_star, self.eye_st.y),
        };
        self.k * star - (c as f64 + 0.5 - at_eye) * self.normal
    }

    fn part(&self, i: i64, j: i64, kind: u32) -> u32 {
        let (a, b) = (
            (i - self.i0).clamp(0, self.ni - 1),
            (j - self.j0).clamp(0, self.nj - 1),
        );
        ((a * self.nj + b) as u32) << 4 | kind
    }

    fn cell_of_part(&self, part: u32) -> (i64, i64) {
        let k = (part >> 4) as i64;
        (self.i0 + k / self.nj, self.j0 + k % self.nj)
    }
}

/// The eight corners of the box centred on `centre` with these spans.
fn box_corners(centre: DVec3, spans: [DVec3; 3]) -> Vec<DVec3> {
    let mut corners = Vec::with_capacity(8);
    for a in [-0.5, 0.5] {
        for b in [-0.5, 0.5] {
            for c in [-0.5, 0.5] {
                corners.push(centre + a * spans[0] + b * spans[1] + c * spans[2]);
            }
        }
    }
    corners
}

impl CellSolid for ViewRotator {
    type Cell = Wedge;

    /// Dr TIM's `getSceneObjectsInPixel` (without derivative control).
    fn cell(&self, i: i64, j: i64) -> Wedge {
        let centre = self.origin + i as f64 * self.p1 + j as f64 * self.p2;
        let d_o = (centre - self.eye).normalize();
        let c = centre + self.offset * d_o;
        let q = c + self.thickness * d_o;
        let d_r = self.rotate_and_magnify * d_o;
        let mu = (self.view_point - self.eye).dot(self.view_normal) / d_r.dot(self.view_normal);
        if !(mu > 0.0 && mu.is_finite()) {
            return None;
        }
        let d_obj = (self.eye + mu * d_r - q).try_normalize()?;
        let n_obj = self.index * d_o - d_obj;
        let along = n_obj.dot(d_obj);
        if along == 0.0 || !along.is_finite() {
            return None;
        }
        Some((c, d_o, q, along.signum() * n_obj))
    }

    fn crossings(
        &self,
        wedge: &Wedge,
        origin: DVec3,
        direction: DVec3,
        mut crossing: impl FnMut(f64, u32),
    ) {
        if let Some((c, d_o, q, n_obj)) = wedge {
            crossing((*c - origin).dot(*d_o) / direction.dot(*d_o), OCULAR);
            crossing((*q - origin).dot(*n_obj) / direction.dot(*n_obj), OBJECTIVE);
        }
    }

    fn inside(&self, wedge: &Wedge, x: DVec3) -> bool {
        wedge.is_some_and(|(c, d_o, q, n_obj)| (x - c).dot(d_o) >= 0.0 && (x - q).dot(n_obj) <= 0.0)
    }

    /// A wall or a face's outward normal points along the line when it leaves the glass,
    /// against it when it enters; a wall crossed into pixel i is pixel i − 1's upper one when
    /// s grows, pixel i's when it shrinks.
    fn hit_part(
        &self,
        i: i64,
        j: i64,
        bound: Bound,
        leaving: bool,
        direction: DVec3,
        signs: [f64; 2],
    ) -> u32 {
        let side = |growing: bool| u32::from(growing != leaving);
        match bound {
            Bound::Surface(kind) => self.part(i, j, kind),
            Bound::Wall(0) => {
                let below = if signs[0] > 0.0 { i - 1 } else { i };
                self.part(below, j, WALL_S | side(signs[0] > 0.0))
            }
            Bound::Wall(_) => {
                let below = if signs[1] > 0.0 { j - 1 } else { j };
                self.part(i, below, WALL_T | side(signs[1] > 0.0))
            }
            Bound::Face(k) => {
                let growing = direction.dot(self.span_stars[k]) > 0.0;
                self.part(i, j, (FACE + 2 * k as u32) | side(growing))
            }
            // The search ended inside the glass: no surface (never reported as a hit).
            Bound::None => self.part(i, j, OCULAR),
        }
    }
}

impl AnalyticShape for ViewRotator {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let o = origin - self.centre;
        let slab = |k: usize| {
            let star = self.span_stars[k];
            (
                o.dot(star),
                direction.dot(star),
                [-0.5, 0.5],
                Bound::Face(k),
            )
        };
        let stretch = clip([slab(0), slab(1), slab(2)], t_min, t_max)?;
        let w = origin - self.eye;
        let coordinates = [
            self.line_coordinate(w, direction, self.p1_star, self.eye_st.x),
            self.line_coordinate(w, direction, self.p2_star, self.eye_st.y),
        ];
        walk(self, origin, direction, t_min, stretch, coordinates)
    }

    fn frame(&self, _p: DVec3, part: u32) -> Frame {
        let kind = part & 15;
        let (i, j) = self.cell_of_part(part);
        let w = match (kind, self.cell(i, j)) {
            (OCULAR, Some((_, d_o, _, _))) => -d_o,
            (OBJECTIVE, Some((_, _, _, n_obj))) => n_obj,
            // A face is only reported on glass.
            (OCULAR | OBJECTIVE, None) => self.normal,
            _ => {
                let sign = if kind & 1 == 0 { 1.0 } else { -1.0 };
                match kind & !1 {
                    WALL_S => sign * self.wall_normal(0, i),
                    WALL_T => sign * self.wall_normal(1, j),
                    face => sign * self.span_stars[((face - FACE) / 2) as usize],
                }
            }
        };
        Frame::from_normal_and_u(w, self.p1)
    }

    /// (s |p₁|, t |p₂|): lengths along the periods of the projection from the eye.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        self.st(p) * DVec2::new(self.p1.length(), self.p2.length())
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some(point_bounds(&box_corners(self.centre, self.spans)))
    }
}
