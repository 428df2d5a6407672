//! A sheet of glass shaped into an array of spherical lenslets (Dr TIM's
//! `RefractiveLensletArray`, whose box's surface `SurfaceOfGeneralRefractiveCLAs` traces each
//! voxel's `RefractiveBoxLens`), traced exactly as one solid.
//!
//! **The lattice.** Lenslet (i, j)'s clear aperture is the parallelogram centred on
//! Aᵢⱼ = A₀₀ + i u + j v spanned by the periods u and v; its principal point is
//! Pᵢⱼ = P₀₀ + i u_P + j v_P (Dr TIM's clear-aperture and principal-point periods, which differ
//! in a Gabor superlens). The optical axis â = (u × v)/|u × v| is normal to the sheet. Points
//! are written x = A₀₀ + s u + t v + z â; lenslet (i, j) covers |s − i| ≤ ½, |t − j| ≤ ½.
//!
//! **A lenslet.** Both surfaces are spheres of radius |R|, R = 2 f (n − 1) (Dr TIM's
//! `RefractiveBoxLens`, the thin-lens lensmaker's equation for radii R and −R), centred on the
//! lenslet's axis (through Pᵢⱼ along â) at Pᵢⱼ ± c â. With ρ the distance from the axis,
//! h(ρ) = √(R² − ρ²) and ζ the axial coordinate from Pᵢⱼ, the glass is |ζ| ≤ g(ρ) with
//!
//! ```text
//! g(ρ) = h(ρ) − c   (f > 0, biconvex),      g(ρ) = c − h(ρ)   (f < 0, biconcave),
//! ```
//!
//! and c is chosen, as Dr TIM's minimum-thickness lenslets, so that the lenslet is d thick
//! (`thickness_at_thinnest_point`, Dr TIM's 0) at its thinnest point in the clear aperture: the
//! farthest corner (distance a) for f > 0, c = √(R² − a²) − d/2; the point nearest the axis
//! (distance b, 0 if the axis passes through the aperture) for f < 0, c = √(R² − b²) + d/2.
//! The whole aperture must lie within |R| of the axis.
//!
//! **The solid.** The glass is the union of the lenslets, cut to the array's parallelogram
//! (`width` × `height` about its centre). Where neighbouring lenslets are both glass at their
//! common edge there is no surface (the sheet is one piece of glass); where one is glass and
//! the other not, a step of the cell wall bounds it (as in a Gabor superlens, where lenslets
//! are off-centre); the array's edges are walls too. A ray walks the cells its path crosses
//! inside the sheet's slab ([`super::cell_walk`]; s and t are linear along it), meeting the
//! cell's two spheres in each.

use glam::{DVec2, DVec3};

use super::cell_walk::{Bound, CellSolid, LineCoordinate, clip, walk};
use super::{AnalyticShape, GeometryError, check_direction, check_point, point_bounds};
use crate::math::{Frame, circle_crossings};

/// The parameters of a lenslet array, as Dr TIM's `RefractiveLensletArray` takes them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LensletArraySpec {
    /// The centre of the array's parallelogram.
    pub centre: DVec3,
    /// The array's extent along u and along v.
    pub width: f64,
    pub height: f64,
    /// The clear-aperture periods u, v.
    pub u_period_clear_aperture: DVec3,
    pub v_period_clear_aperture: DVec3,
    /// The principal-point periods u_P, v_P.
    pub u_period_principal_point: DVec3,
    pub v_period_principal_point: DVec3,
    /// A₀₀ and P₀₀.
    pub clear_aperture_centre: DVec3,
    pub principal_point_centre: DVec3,
    /// f ≠ 0, n > 1: R = 2 f (n − 1).
    pub focal_length: f64,
    pub refractive_index: f64,
    /// d ≥ 0.
    pub thickness_at_thinnest_point: f64,
}

/// The most lenslets an array may have (each hit names its lenslet in 29 bits).
const MAX_LENSLETS: i64 = 1 << 29;

/// The parts a hit can be on, in the low 3 bits of the part number (the lenslet's index above
/// them): the sphere centred at P + c â or P − c â, or a wall whose outward normal is ±u* or
/// ±v* (u*, v* the reciprocal vectors of the lattice, normal to the walls).
const FRONT: u32 = 0;
const BACK: u32 = 1;
const WALL_S: u32 = 2;
const WALL_T: u32 = 4;

#[derive(Debug, Clone, PartialEq)]
pub struct LensletArray {
    a00: DVec3,
    u: DVec3,
    v: DVec3,
    /// Reciprocal vectors: s = (x − A₀₀)·u*, t = (x − A₀₀)·v*.
    u_star: DVec3,
    v_star: DVec3,
    /// â, unit.
    axis: DVec3,
    p00: DVec3,
    pu: DVec3,
    pv: DVec3,
    /// |R|.
    radius: f64,
    converging: bool,
    thinnest: f64,
    /// The array's range of s, t and z.
    s_range: [f64; 2],
    t_range: [f64; 2],
    z_range: [f64; 2],
    /// The first lenslet's indices and the number of lenslets along v.
    i0: i64,
    j0: i64,
    ni: i64,
    nj: i64,
}

/// Lenslet (i, j): its principal point and the offset c of its spheres' centres.
pub(super) struct Lenslet {
    p: DVec3,
    c: f64,
}

impl LensletArray {
    pub fn new(spec: &LensletArraySpec) -> Result<LensletArray, GeometryError> {
        let bad = |why: String| Err(GeometryError::Degenerate(why));
        for (what, p) in [
            ("centre", spec.centre),
            ("clear_aperture_centre", spec.clear_aperture_centre),
            ("principal_point_centre", spec.principal_point_centre),
            ("u_period_principal_point", spec.u_period_principal_point),
            ("v_period_principal_point", spec.v_period_principal_point),
        ] {
            check_point(what, p)?;
        }
        let (u, v) = (spec.u_period_clear_aperture, spec.v_period_clear_aperture);
        check_direction("u_period_clear_aperture", u)?;
        check_direction("v_period_clear_aperture", v)?;
        let normal = u.cross(v);
        let Some(axis) = normal.try_normalize() else {
            return bad("the clear-aperture periods u and v are parallel".into());
        };
        if normal.length() < 1e-9 * u.length() * v.length() {
            return bad("the clear-aperture periods u and v are (nearly) parallel".into());
        }
        // The glass lies about the principal points; the centres place the lattice across
        // the sheet and must lie in its plane.
        let p00 = spec.principal_point_centre;
        let tolerance = 1e-9 * (u.length() + v.length() + (p00 - spec.centre).length());
        for (what, point) in [
            ("centre", spec.centre),
            ("clear_aperture_centre", spec.clear_aperture_centre),
        ] {
            if (point - p00).dot(axis).abs() > tolerance {
                return bad(format!(
                    "{what} must lie in the plane of the principal point principal_point_centre \
                     across the optical axis u × v (it is {} off it along the axis)",
                    (point - p00).dot(axis)
                ));
            }
        }
        let (f, n) = (spec.focal_length, spec.refractive_index);
        let u_star = v.cross(axis) / u.dot(v.cross(axis));
        let v_star = axis.cross(u) / v.dot(axis.cross(u));
        let (a00, centre) = (spec.clear_aperture_centre, spec.centre);
        let (sc, tc) = ((centre - a00).dot(u_star), (centre - a00).dot(v_star));
        let (hs, ht) = (
            0.5 * spec.width / u.length(),
            0.5 * spec.height / v.length(),
        );
        let (s_range, t_range) = ([sc - hs, sc + hs], [tc - ht, tc + ht]);
        // The first and last lenslets the ranges reach into (an edge on a cell boundary adds
        // no lenslet beyond it).
        let (first, last) = (
            |x: f64| (x + 0.5).floor() as i64,
            |x: f64| (x - 0.5).ceil() as i64,
        );
        let (i0, i1, j0, j1) = (
            first(s_range[0]),
            last(s_range[1]),
            first(t_range[0]),
            last(t_range[1]),
        );
        let (ni, nj) = (
            i1.saturating_sub(i0).saturating_add(1),
            j1.saturating_sub(j0).saturating_add(1),
        );
        if ni.saturating_mul(nj) > MAX_LENSLETS {
            return bad(format!(
                "the array has about {:.3e} lenslets ({} × {} periods), more than {MAX_LENSLETS}",
                (2.0 * hs + 1.0) * (2.0 * ht + 1.0),
                2.0 * hs,
                2.0 * ht
            ));
        }
        let mut array = LensletArray {
            a00,
            u,
            v,
            u_star,
            v_star,
            axis,
            p00: spec.principal_point_centre,
            pu: spec.u_period_principal_point,
            pv: spec.v_period_principal_point,
            radius: (2.0 * f * (n - 1.0)).abs(),
            converging: f > 0.0,
            thinnest: spec.thickness_at_thinnest_point,
            s_range,
            t_range,
            z_range: [0.0; 2],
            i0,
            j0,
            ni,
            nj,
        };
        // The aperture's distance from the axis, the principal point's height and the glass's
        // half-thickness are extreme at the corner lenslets (convex or affine in i, j).
        let (mut z_lo, mut z_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for (i, j) in [(i0, j0), (i0, j1), (i1, j0), (i1, j1)] {
            let (near, far) = array.aperture_distances(i, j);
            if far > array.radius {
                return bad(format!(
                    "lenslet ({i}, {j})'s clear aperture reaches {far} from its optical axis, \
                     beyond the radius of curvature |2 f (n − 1)| = {}",
                    array.radius
                ));
            }
            let lenslet = array.lenslet(i, j, near, far);
            let half = match array.converging {
                true => array.radius - lenslet.c,
                false => lenslet.c - (array.radius * array.radius - far * far).sqrt(),
            };
            let z = (lenslet.p - a00).dot(axis);
            z_lo = z_lo.min(z - half);
            z_hi = z_hi.max(z + half);
        }
        let margin = 1e-9 * (z_hi - z_lo).max(u.length().max(v.length()));
        array.z_range = [z_lo - margin, z_hi + margin];
        Ok(array)
    }

    /// The distances from lenslet (i, j)'s axis to the nearest and the farthest point of its
    /// clear aperture.
    fn aperture_distances(&self, i: i64, j: i64) -> (f64, f64) {
        let (fi, fj) = (i as f64, j as f64);
        let flat = |x: DVec3| x - x.dot(self.axis) * self.axis;
        // The aperture's centre and corners relative to the principal point, across the axis.
        let offset = flat(self.a00 + fi * self.u + fj * self.v - self.principal_point(i, j));
        let corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            .map(|(a, b)| offset + a * self.u + b * self.v);
        let far = corners.iter().map(|c| c.length()).fold(0.0, f64::max);
        let (s, t) = (-offset.dot(self.u_star), -offset.dot(self.v_star));
        let near = if s.abs() <= 0.5 && t.abs() <= 0.5 {
            0.0
        } else {
            (0..4)
                .map(|k| segment_distance(corners[k], corners[(k + 1) % 4]))
                .fold(f64::INFINITY, f64::min)
        };
        (near, far)
    }

    fn principal_point(&self, i: i64, j: i64) -> DVec3 {
        self.p00 + i as f64 * self.pu + j as f64 * self.pv
    }

    /// Lenslet (i, j), given its aperture's distances from its axis.
    fn lenslet(&self, i: i64, j: i64, near: f64, far: f64) -> Lenslet {
        let r2 = self.radius * self.radius;
        let c = if self.converging {
            (r2 - far * far).sqrt() - 0.5 * self.thinnest
        } else {
            (r2 - near * near).sqrt() + 0.5 * self.thinnest
        };
        Lenslet {
            p: self.principal_point(i, j),
            c,
        }
    }

    fn lenslet_at(&self, i: i64, j: i64) -> Lenslet {
        let (near, far) = self.aperture_distances(i, j);
        self.lenslet(i, j, near, far)
    }

    /// The part number of `kind` in lenslet (i, j) (an index off the array by rounding taken
    /// as the nearest lenslet's).
    fn part(&self, i: i64, j: i64, kind: u32) -> u32 {
        let (a, b) = (
            (i - self.i0).clamp(0, self.ni - 1),
            (j - self.j0).clamp(0, self.nj - 1),
        );
        ((a * self.nj + b) as u32) << 3 | kind
    }

    fn cell_of_part(&self, part: u32) -> (i64, i64) {
        let k = (part >> 3) as i64;
        (self.i0 + k / self.nj, self.j0 + k % self.nj)
    }
}

/// The distance from the origin to the segment from `a` to `b`.
fn segment_distance(a: DVec3, b: DVec3) -> f64 {
    let e = b - a;
    let k = (-a.dot(e) / e.length_squared()).clamp(0.0, 1.0);
    (a + k * e).length()
}

impl CellSolid for LensletArray {
    type Cell = Lenslet;

    fn cell(&self, i: i64, j: i64) -> Lenslet {
        self.lenslet_at(i, j)
    }

    /// The crossings of the lenslet's two spheres.
    fn crossings(
        &self,
        lenslet: &Lenslet,
        origin: DVec3,
        direction: DVec3,
        mut crossing: impl FnMut(f64, u32),
    ) {
        for (kind, sign) in [(FRONT, 1.0), (BACK, -1.0)] {
            let centre = lenslet.p + sign * lenslet.c * self.axis;
            if let Some((r0, r1)) = circle_crossings(origin - centre, direction, self.radius) {
                crossing(r0, kind);
                crossing(r1, kind);
            }
        }
    }

    /// |ζ| ≤ g(ρ).
    fn inside(&self, lenslet: &Lenslet, x: DVec3) -> bool {
        let rel = x - lenslet.p;
        let zeta = rel.dot(self.axis);
        let rho2 = (rel - zeta * self.axis).length_squared();
        let h = (self.radius * self.radius - rho2).max(0.0).sqrt();
        let g = if self.converging {
            h - lenslet.c
        } else {
            lenslet.c - h
        };
        zeta.abs() <= g
    }

    /// A wall's outward normal points along the line when it leaves the glass, against it
    /// when it enters.
    fn hit_part(
        &self,
        i: i64,
        j: i64,
        bound: Bound,
        leaving: bool,
        _direction: DVec3,
        [ds, dt]: [f64; 2],
    ) -> u32 {
        let wall = |base: u32, d: f64| base | u32::from((d > 0.0) != leaving);
        let kind = match bound {
            Bound::Surface(kind) => kind,
            Bound::Wall(0) => wall(WALL_S, ds),
            Bound::Wall(_) => wall(WALL_T, dt),
            // The slab's faces across the axis never touch the glass; keep the nearest
            // sphere's part.
            Bound::Face(_) | Bound::None => FRONT,
        };
        self.part(i, j, kind)
    }
}

impl AnalyticShape for LensletArray {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let o = origin - self.a00;
        let (s, t) = (
            LineCoordinate::linear(o.dot(self.u_star), direction.dot(self.u_star)),
            LineCoordinate::linear(o.dot(self.v_star), direction.dot(self.v_star)),
        );
        let stretch = clip(
            [
                (
                    o.dot(self.u_star),
                    direction.dot(self.u_star),
                    self.s_range,
                    Bound::Wall(0),
                ),
                (
                    o.dot(self.v_star),
                    direction.dot(self.v_star),
                    self.t_range,
                    Bound::Wall(1),
                ),
                (
                    o.dot(self.axis),
                    direction.dot(self.axis),
                    self.z_range,
                    Bound::None,
                ),
            ],
            t_min,
            t_max,
        )?;
        walk(self, origin, direction, t_min, stretch, [s, t])
    }

    fn frame(&self, p: DVec3, part: u32) -> Frame {
        let kind = part & 7;
        let (w, hint) = match kind {
            FRONT | BACK => {
                let (i, j) = self.cell_of_part(part);
                let lenslet = self.lenslet_at(i, j);
                let sign = if kind == FRONT { 1.0 } else { -1.0 };
                let out = p - (lenslet.p + sign * lenslet.c * self.axis);
                (if self.converging { out } else { -out }, self.u)
            }
            _ => {
                let sign = if kind & 1 == 0 { 1.0 } else { -1.0 };
                match kind & !1 {
                    WALL_S => (sign * self.u_star, self.v),
                    _ => (sign * self.v_star, self.u),
                }
            }
        };
        Frame::from_normal_and_u(w, hint)
    }

    /// (s |u|, t |v|): lengths along the clear-aperture periods from A₀₀.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let x = p - self.a00;
        DVec2::new(
            x.dot(self.u_star) * self.u.length(),
            x.dot(self.v_star) * self.v.length(),
        )
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut corners = Vec::with_capacity(8);
        for s in self.s_range {
            for t in self.t_range {
                for z in self.z_range {
                    corners.push(self.a00 + s * self.u + t * self.v + z * self.axis);
                }
            }
        }
        Some(point_bounds(&corners))
    }
}
