//! Confocal lenslet arrays (Dr TIM's `EditableCLAs`, "CLAs that can be configured in a number
//! of ways"): two rectangular arrays of ideal thin lenslets that share their focal plane, so that
//! each pair of lenslets is a small telescope, with optional baffles between the telescopes and
//! optional channeling lenses in front of the arrays.
//!
//! With C the centre of the common focal plane, n̂ the outwards normal to lenslet array 1
//! (normalised), u and v the span vectors made perpendicular to n̂ (Dr TIM's
//! `getPartPerpendicularTo`, not normalised: they give the arrays' size) and û, v̂ their
//! directions (Dr TIM's `populateSceneObjectCollection`):
//!
//! - lenslet array 1 is the parallelogram centred on C + f₁ n̂ spanned by u and v, lenslet array
//!   2 the one centred on C − f₂ n̂; each is a rectangular array of ideal thin lenslets of its
//!   focal length with the periods `period_u`, `period_v`, offsets 0 and transmission
//!   coefficient 1 (Dr TIM's `RectangularIdealThinLensletArray`). Dr TIM's lenslet array finds
//!   the lenslet centres in the parallelogram's scaled surface coordinates, which run from
//!   −|u|/2 to |u|/2 along u (and likewise along v) and are 0 at the parallelogram's centre, so
//!   with offsets 0 the lenslet centres are the lattice points centre + i p_u û + j p_v v̂
//!   (oblique coordinates where u and v are not perpendicular): timbre's
//!   `ideal-thin-lenslet-array` centred on the parallelogram's centre.
//! - The baffles: Dr TIM's `EditableCuboid` centred on C + ½(f₁ − f₂) n̂ with the half-depth
//!   ½(f₁ + f₂) − TINY along n̂ (TINY = 10⁻⁴, Dr TIM's `MyMath.TINY`) and the half-widths ½u and
//!   ½v (the slab {|(x − C)·û| ≤ |u|/2, |(x − C)·v̂| ≤ |v|/2} between the arrays, each face
//!   normal to its vector), whose surface is a `SurfaceOfVolumeWithColouredVoxelBoundaries`: its
//!   inside is divided into voxels by the planes normal to û and to v̂ through C + ½p_u û +
//!   ½p_v v̂, spaced p_u and p_v, and a ray inside that meets one of them takes its colour,
//!   black. Here they are black sheets (`constant-colour` black, which absorbs, as the voxel
//!   boundaries' colour does), one per plane that crosses the slab: the plane's intersection
//!   with the slab, a rectangle. A sheet lies inside the slab, so a ray can only meet it at a
//!   point inside the slab, which a straight ray from outside reaches only through the slab's
//!   surface; there Dr TIM starts following it through the voxels, and it is absorbed at the
//!   first plane it meets, the plane of the first sheet it meets here. A ray that starts inside
//!   (Dr TIM: one that leaves the volume having met no surface of it) is followed from its
//!   start in both. So every ray meets the same baffles as in Dr TIM (see docs/SCENE_FORMAT.md
//!   for the small differences: Dr TIM's TINY steps, and objects inside the slab).
//! - The channeling lenses: ideal thin lenses (or what `channeling_lenses_type` makes them)
//!   filling the parallelograms centred on C + (f₁ + TINY) n̂ (optical axis n̂) and
//!   C − (f₂ + TINY) n̂ (optical axis −n̂), of focal lengths `channeling_lens1_f` and
//!   `channeling_lens2_f` and Dr TIM's transmission coefficient 0.96.
//!
//! A ray through one telescope (array 1 first) leaves with its slope d_t/|d·n̂| along û and v̂
//! divided by η = −f₂/f₁ (the gCLAs' Eq 39, with no offset): after lenslet 1 (centre P₁, the ray
//! at P₁ + r with slope t) the slope is t − r/f₁, lenslet 2 is met at P₂ + r + (f₁ + f₂)(t −
//! r/f₁), and after it the slope is t − r/f₁ − (r + (f₁ + f₂)(t − r/f₁))/f₂ = −(f₁/f₂) t,
//! whatever r.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{Edges, Face, LensDevice, LensType, Part, semitransparent_plane};
use crate::geometry::{Parallelogram, Shape};
use crate::keys::{Direction, NonZero, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::metatoys::{Phase, RectangularLensletArrayPhase};
use crate::surfaces::{LensletArray, PhaseHologram, Surface, ThinLens, Transparent};

/// Dr TIM's `MyMath.TINY`: the baffles stop this short of each lenslet array, and the
/// channeling lenses lie this far beyond them.
pub const TINY: f64 = 1e-4;

/// The channeling lenses' transmission coefficient (Dr TIM's, which it does not let one change).
pub const CHANNELING_LENS_TRANSMISSION_COEFFICIENT: f64 = 0.96;

/// Most baffle sheets across each of u and v (checked before any is made): one sheet per
/// period, so at most this many telescopes across each. Each sheet is a scene object; at the
/// limit the device is 20 004 objects.
pub const MAX_BAFFLES: u64 = 10_000;

#[derive(Debug, Clone, PartialEq)]
pub struct Clas {
    pub centre_of_common_focal_plane: DVec3,
    /// The arrays' width vector and first direction of periodicity (its part perpendicular to
    /// the normal is used).
    pub span_vector_u: DVec3,
    /// The arrays' height vector and second direction of periodicity.
    pub span_vector_v: DVec3,
    /// Unit normal to lenslet array 1, pointing away from array 2 (for f₁, f₂ > 0).
    pub outwards_normal_to_la1: DVec3,
    /// Focal lengths of lenslet arrays 1 and 2, non-zero.
    pub f1: f64,
    pub f2: f64,
    /// The lenslets' periods along û and v̂, positive.
    pub period_u: f64,
    pub period_v: f64,
    pub lenslet_array_type: LensType,
    pub show_baffles: bool,
    pub show_channeling_lens1: bool,
    pub show_channeling_lens2: bool,
    pub channeling_lens1_f: f64,
    pub channeling_lens2_f: f64,
    pub channeling_lenses_type: LensType,
    pub simulate_diffractive_blur: bool,
    /// The wavelength for the diffractive blur.
    pub lambda: f64,
}

/// The arrays' plane: C, n̂, and u, v perpendicular to n̂.
struct Frame {
    c: DVec3,
    n: DVec3,
    u: DVec3,
    v: DVec3,
}

impl Frame {
    /// The parallelogram centred on `centre` spanned by u and v (Dr TIM's
    /// `EditableScaledParametrisedCentredParallelogram`).
    fn face(&self, centre: DVec3) -> Face {
        Face::Parallelogram {
            corner: centre - 0.5 * self.u - 0.5 * self.v,
            span_u: self.u,
            span_v: self.v,
        }
    }
}

impl Clas {
    fn frame(&self) -> Result<Frame, String> {
        let n = self.outwards_normal_to_la1.normalize();
        let perpendicular = |key: &str, span: DVec3| {
            let p = span.reject_from_normalized(n);
            if p.length() <= 1e-9 * span.length() {
                Err(format!(
                    "{key} = {span} has no part perpendicular to outwards_normal_to_la1 = {} \
                     (it is zero or parallel to it)",
                    self.outwards_normal_to_la1
                ))
            } else {
                Ok(p)
            }
        };
        let u = perpendicular("span_vector_u", self.span_vector_u)?;
        let v = perpendicular("span_vector_v", self.span_vector_v)?;
        if u.normalize().cross(v.normalize()).length() < 1e-9 {
            return Err(format!(
                "span_vector_v = {} is parallel to span_vector_u = {} in the plane of the arrays \
                 (their parts perpendicular to outwards_normal_to_la1)",
                self.span_vector_v, self.span_vector_u
            ));
        }
        Ok(Frame {
            c: self.centre_of_common_focal_plane,
            n,
            u,
            v,
        })
    }

    /// Lenslet array `name` of focal length `f` centred on `centre`, or none (`none`).
    fn lenslet_array(
        &self,
        frame: &Frame,
        name: &str,
        centre: DVec3,
        f: f64,
    ) -> Result<Option<Part>, String> {
        let (u, v) = (frame.u.normalize(), frame.v.normalize());
        let shape = Parallelogram::new(centre - 0.5 * frame.u - 0.5 * frame.v, frame.u, frame.v)
            .map(Shape::Parallelogram)
            .map_err(|e| format!("{name}: {e}"))?;
        let period = DVec2::new(self.period_u, self.period_v);
        let surface = match self.lenslet_array_type {
            LensType::NoLens => return Ok(None),
            LensType::IdealThinLens => Surface::IdealThinLensletArray(LensletArray {
                centre,
                u,
                v,
                period,
                focal_length: f,
                transmission_coefficient: 1.0,
                lambda: self.simulate_diffractive_blur.then_some(self.lambda),
            }),
            LensType::LensHologram => {
                // Dr TIM's `PhaseHologramOfRectangularLensletArray` about the array's centre.
                if self.simulate_diffractive_blur {
                    return Err(
                        "lenslet_array_type = \"lens-hologram\" cannot simulate_diffractive_blur: \
                         timbre's phase holograms do not simulate diffraction (use \
                         \"ideal-thin-lens\" lenslet arrays for the blur)"
                            .into(),
                    );
                }
                if u.dot(v).abs() > 1e-9 {
                    return Err(format!(
                        "lenslet_array_type = \"lens-hologram\" needs span_vector_u and \
                         span_vector_v perpendicular in the plane of the arrays (their parts \
                         perpendicular to the normal are {} and {}): timbre's \
                         rectangular-lenslet-array phase has a rectangular lattice",
                        frame.u, frame.v
                    ));
                }
                let lattice = shape
                    .plane_coordinates(centre, 0)
                    .expect("a parallelogram has plane coordinates");
                Surface::PhaseHologram(PhaseHologram {
                    phase: Phase::RectangularLensletArray(RectangularLensletArrayPhase {
                        focal_length: f,
                        period,
                        centre: lattice,
                    }),
                    transmission_coefficient: 1.0,
                    reflection_coefficient: 1.0,
                })
            }
            LensType::GlassPane => Surface::Transparent(Transparent {
                transmission_coefficient: 1.0,
            }),
            LensType::SemitransparentPlane => semitransparent_plane(),
        };
        Ok(Some(Part {
            name: name.into(),
            shape,
            surface,
            edge: false,
        }))
    }

    /// The baffle sheets `baffle {label} I`: the planes normal to `across` (unit, in the
    /// arrays' plane) at `first` + k `period` from C along it, each cut to the slab of
    /// half-width `half` along `across` and `other_half` along the unit `other`, and between
    /// `depth.0` and `depth.1` along n̂ from C.
    fn baffles(
        &self,
        frame: &Frame,
        label: &str,
        (across, half, period, first): (DVec3, f64, f64, f64),
        (other, other_half): (DVec3, f64),
        depth: (f64, f64),
    ) -> Result<Vec<Part>, String> {
        // Planes k_lo ..= k_hi lie within the slab, strictly (one on a face makes no sheet).
        let inside = |a: f64| a.abs() < half * (1.0 - 1e-9);
        let k_lo = ((-half - first) / period).ceil();
        let k_hi = ((half - first) / period).floor();
        if k_hi - k_lo + 1.0 > MAX_BAFFLES as f64 {
            return Err(format!(
                "show_baffles: {} baffles across {label} (the width {} over period_{label} = \
                 {period}) exceed the limit of {MAX_BAFFLES} (each is a scene object); use a \
                 larger period or show_baffles = false",
                k_hi - k_lo + 1.0,
                2.0 * half
            ));
        }
        // Along the sheet, in the arrays' plane: w ⟂ `across`; its points a·across + s w meet
        // the slab's faces normal to `other` where a g + s σ = ±`other_half`.
        let w = frame.n.cross(across);
        let (g, sigma) = (across.dot(other), w.dot(other));
        let mut parts = Vec::new();
        for k in (k_lo as i64)..=(k_hi as i64) {
            let a = first + k as f64 * period;
            if !inside(a) {
                continue;
            }
            let ends = [(-other_half - a * g) / sigma, (other_half - a * g) / sigma];
            let (s_lo, s_hi) = (ends[0].min(ends[1]), ends[0].max(ends[1]));
            let name = format!("baffle {label} {}", parts.len() + 1);
            let shape = Parallelogram::new(
                frame.c + a * across + s_lo * w + depth.0 * frame.n,
                (s_hi - s_lo) * w,
                (depth.1 - depth.0) * frame.n,
            )
            .map_err(|e| format!("{name}: {e}"))?;
            parts.push(Part {
                name,
                shape: Shape::Parallelogram(shape),
                // Dr TIM's voxel boundaries' colour, `DoubleColour.BLACK`, unlit.
                surface: Surface::ConstantColour(Colour::ZERO),
                edge: false,
            });
        }
        Ok(parts)
    }
}

impl LensDevice for Clas {
    /// `lenslet array 1`, `lenslet array 2`, with `show_baffles` the baffles `baffle u I` (the
    /// sheets normal to û, I = 1, 2, … along û) and `baffle v J`, and the shown channeling
    /// lenses `channeling lens 1`, `channeling lens 2`; no edges.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("CLAs have no edges to show (show_edges)".into());
        }
        let frame = self.frame()?;
        let (c, n) = (frame.c, frame.n);
        let mut parts = Vec::new();
        parts.extend(self.lenslet_array(&frame, "lenslet array 1", c + self.f1 * n, self.f1)?);
        parts.extend(self.lenslet_array(&frame, "lenslet array 2", c - self.f2 * n, self.f2)?);
        if self.show_baffles {
            // Between the arrays (at f₁ and −f₂ along n̂), TINY short of each.
            let (mid, gap) = (0.5 * (self.f1 - self.f2), 0.5 * (self.f1 + self.f2).abs());
            if gap <= TINY {
                return Err(format!(
                    "show_baffles: the lenslet arrays are |f1 + f2| = {} apart, which leaves no \
                     room for baffles between them (they stop TINY = {TINY} short of each \
                     array); set show_baffles = false",
                    2.0 * gap
                ));
            }
            let depth = (mid - gap + TINY, mid + gap - TINY);
            let (u, v) = (frame.u.normalize(), frame.v.normalize());
            let (hu, hv) = (0.5 * frame.u.length(), 0.5 * frame.v.length());
            // The planes pass through C + ½p_u û + ½p_v v̂.
            let point = 0.5 * self.period_u * u + 0.5 * self.period_v * v;
            parts.extend(self.baffles(
                &frame,
                "u",
                (u, hu, self.period_u, point.dot(u)),
                (v, hv),
                depth,
            )?);
            parts.extend(self.baffles(
                &frame,
                "v",
                (v, hv, self.period_v, point.dot(v)),
                (u, hu),
                depth,
            )?);
        }
        let channeling = [
            (
                self.show_channeling_lens1,
                "channeling lens 1",
                c + (self.f1 + TINY) * n,
                n,
                self.channeling_lens1_f,
            ),
            (
                self.show_channeling_lens2,
                "channeling lens 2",
                c - (self.f2 + TINY) * n,
                -n,
                self.channeling_lens2_f,
            ),
        ];
        for (shown, name, principal_point, optical_axis, focal_length) in channeling {
            if !shown {
                continue;
            }
            let lens = ThinLens {
                principal_point,
                optical_axis,
                focal_length,
                gradient: None,
                transmission_coefficient: CHANNELING_LENS_TRANSMISSION_COEFFICIENT,
            };
            parts.extend(self.channeling_lenses_type.part(
                name.into(),
                frame.face(principal_point),
                lens,
            )?);
        }
        Ok(parts)
    }
}

/// `lenses = { type = "clas" }`: Dr TIM's `EditableCLAs`, with the defaults of its constructor
/// `EditableCLAs(description, parent, studio)` for every key not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClasKeys {
    centre_of_common_focal_plane: Option<Vector>,
    span_vector_u: Option<Vector>,
    span_vector_v: Option<Vector>,
    outwards_normal_to_la1: Option<Direction>,
    f1: Option<NonZero>,
    f2: Option<NonZero>,
    period_u: Option<Positive>,
    period_v: Option<Positive>,
    lenslet_array_type: Option<LensType>,
    show_baffles: Option<bool>,
    show_channeling_lens1: Option<bool>,
    show_channeling_lens2: Option<bool>,
    channeling_lens1_f: Option<NonZero>,
    channeling_lens2_f: Option<NonZero>,
    channeling_lenses_type: Option<LensType>,
    simulate_diffractive_blur: Option<bool>,
    lambda: Option<Positive>,
}

impl ClasKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        Ok(Box::new(Clas {
            centre_of_common_focal_plane: self
                .centre_of_common_focal_plane
                .map_or(DVec3::new(0.0, 0.0, 5.0), |c| c.0),
            span_vector_u: self.span_vector_u.map_or(DVec3::X, |u| u.0),
            span_vector_v: self.span_vector_v.map_or(DVec3::Y, |v| v.0),
            outwards_normal_to_la1: self.outwards_normal_to_la1.map_or(DVec3::Z, |n| n.0),
            f1: self.f1.map_or(0.1, |f| f.0),
            f2: self.f2.map_or(0.1, |f| f.0),
            period_u: self.period_u.map_or(0.1, |p| p.0),
            period_v: self.period_v.map_or(0.1, |p| p.0),
            lenslet_array_type: self.lenslet_array_type.unwrap_or_default(),
            show_baffles: self.show_baffles.unwrap_or(true),
            show_channeling_lens1: self.show_channeling_lens1.unwrap_or(false),
            show_channeling_lens2: self.show_channeling_lens2.unwrap_or(false),
            channeling_lens1_f: self.channeling_lens1_f.map_or(1.0, |f| f.0),
            channeling_lens2_f: self.channeling_lens2_f.map_or(1.0, |f| f.0),
            channeling_lenses_type: self.channeling_lenses_type.unwrap_or_default(),
            simulate_diffractive_blur: self.simulate_diffractive_blur.unwrap_or(false),
            lambda: self.lambda.map_or(633e-9, |l| l.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dr TIM's default CLAs (`EditableCLAs(description, parent, studio)`), written out.
    fn default_clas() -> Clas {
        Clas {
            centre_of_common_focal_plane: DVec3::new(0.0, 0.0, 5.0),
            span_vector_u: DVec3::X,
            span_vector_v: DVec3::Y,
            outwards_normal_to_la1: DVec3::Z,
            f1: 0.1,
            f2: 0.1,
            period_u: 0.1,
            period_v: 0.1,
            lenslet_array_type: LensType::IdealThinLens,
            show_baffles: true,
            show_channeling_lens1: false,
            show_channeling_lens2: false,
            channeling_lens1_f: 1.0,
            channeling_lens2_f: 1.0,
            channeling_lenses_type: LensType::IdealThinLens,
            simulate_diffractive_blur: false,
            lambda: 633e-9,
        }
    }

    fn part<'a>(parts: &'a [Part], name: &str) -> &'a Part {
        parts
            .iter()
            .find(|p| p.name == name)
            .unwrap_or_else(|| panic!("no {name}"))
    }

    /// The parallelogram of a part: (corner, span_u, span_v).
    fn parallelogram(p: &Part) -> (DVec3, DVec3, DVec3) {
        let Shape::Parallelogram(s) = &p.shape else {
            panic!("{}: {:?}", p.name, p.shape)
        };
        (s.corner(), s.span_u(), s.span_v())
    }

    #[track_caller]
    fn close(a: DVec3, b: DVec3) {
        assert!((a - b).length() < 1e-12, "{a} != {b}");
    }

    /// The keys `{}` are Dr TIM's default CLAs.
    #[test]
    fn no_keys_make_dr_tims_default() {
        let keys: ClasKeys = toml::from_str("").unwrap();
        let built = format!("{:?}", keys.build().unwrap());
        assert_eq!(built, format!("{:?}", default_clas()));
    }

    /// Dr TIM's default: LA1 the unit square at z = 5 + 0.1, LA2 at z = 5 − 0.1, both ideal
    /// lenslet arrays of f = 0.1 and periods 0.1 centred on the squares' centres with
    /// transmission 1; the baffle planes x = 0.05 + 0.1k and y = 0.05 + 0.1k, ten of each
    /// within the unit square, from z = 4.9 + TINY to 5.1 − TINY.
    #[test]
    fn the_default_parts_sit_where_dr_tim_puts_them() {
        let parts = default_clas().parts(None).unwrap();
        assert_eq!(parts.len(), 2 + 10 + 10);
        for (name, z) in [("lenslet array 1", 5.1), ("lenslet array 2", 4.9)] {
            let p = part(&parts, name);
            let (corner, su, sv) = parallelogram(p);
            close(corner, DVec3::new(-0.5, -0.5, z));
            close(su, DVec3::X);
            close(sv, DVec3::Y);
            let Surface::IdealThinLensletArray(a) = &p.surface else {
                panic!("{:?}", p.surface)
            };
            close(a.centre, DVec3::new(0.0, 0.0, z));
            assert_eq!(
                (a.u, a.v, a.period, a.focal_length),
                (DVec3::X, DVec3::Y, DVec2::splat(0.1), 0.1)
            );
            assert_eq!((a.transmission_coefficient, a.lambda), (1.0, None));
        }
        for i in 0..10 {
            let x = -0.45 + 0.1 * i as f64;
            let (corner, su, sv) = parallelogram(part(&parts, &format!("baffle u {}", i + 1)));
            // The sheet x = const from y = −0.5 to 0.5 (in either order), z from 4.9001 to 5.0999.
            let ys = [corner.y, corner.y + su.y + sv.y];
            assert!(
                (ys[0].min(ys[1]) + 0.5).abs() < 1e-12 && (ys[0].max(ys[1]) - 0.5).abs() < 1e-12
            );
            assert!(
                (corner.x - x).abs() < 1e-12 && su.x == 0.0 && sv.x == 0.0,
                "{corner}"
            );
            assert!((corner.z - 4.9001).abs() < 1e-12 && (sv.z - 0.1998).abs() < 1e-12);
            let (corner, su, sv) = parallelogram(part(&parts, &format!("baffle v {}", i + 1)));
            assert!(
                (corner.y - x).abs() < 1e-12 && su.y == 0.0 && sv.y == 0.0,
                "{corner}"
            );
            let xs = [corner.x, corner.x + su.x + sv.x];
            assert!(
                (xs[0].min(xs[1]) + 0.5).abs() < 1e-12 && (xs[0].max(xs[1]) - 0.5).abs() < 1e-12
            );
        }
        for p in &parts[2..] {
            assert_eq!(
                p.surface,
                Surface::ConstantColour(Colour::ZERO),
                "{}",
                p.name
            );
            assert!(!p.edge);
        }
    }

    /// The channeling lenses lie TINY beyond the arrays, with Dr TIM's 0.96, the second's axis
    /// reversed; here with f₂ < 0 (LA2 on LA1's side of the focal plane, at C + 0.05 n̂).
    #[test]
    fn the_channeling_lenses_lie_tiny_beyond_the_arrays() {
        let clas = Clas {
            centre_of_common_focal_plane: DVec3::new(1.0, 2.0, 3.0),
            outwards_normal_to_la1: DVec3::new(0.0, 0.0, -1.0),
            span_vector_u: DVec3::new(2.0, 0.0, 0.7),
            span_vector_v: DVec3::new(0.0, 1.5, 0.0),
            f2: -0.05,
            show_channeling_lens1: true,
            show_channeling_lens2: true,
            channeling_lens1_f: 2.0,
            channeling_lens2_f: -3.0,
            ..default_clas()
        };
        let parts = clas.parts(None).unwrap();
        // LA1 at 3 − 0.1, LA2 at 3 − 0.05 (both on the −z side); the u span loses its z part.
        let (corner, su, sv) = parallelogram(part(&parts, "lenslet array 1"));
        close(corner + 0.5 * (su + sv), DVec3::new(1.0, 2.0, 2.9));
        close(su, DVec3::new(2.0, 0.0, 0.0));
        let (corner, su, sv) = parallelogram(part(&parts, "lenslet array 2"));
        close(corner + 0.5 * (su + sv), DVec3::new(1.0, 2.0, 2.95));
        let Surface::IdealThinLensletArray(a) = &part(&parts, "lenslet array 2").surface else {
            panic!()
        };
        assert_eq!(a.focal_length, -0.05);
        // Baffles between z = 2.95 + TINY and 2.9 − TINY.
        let (corner, _, sv) = parallelogram(part(&parts, "baffle u 1"));
        assert!((corner.z - 2.9499).abs() < 1e-12 && (sv.z + 0.0498).abs() < 1e-12);
        for (name, p, axis, f) in [
            ("channeling lens 1", 3.0 - 0.1 - TINY, -1.0, 2.0),
            ("channeling lens 2", 3.0 - 0.05 + TINY, 1.0, -3.0),
        ] {
            let Surface::IdealThinLens(lens) = &part(&parts, name).surface else {
                panic!("{name}")
            };
            close(lens.principal_point, DVec3::new(1.0, 2.0, p));
            close(lens.optical_axis, DVec3::new(0.0, 0.0, axis));
            assert_eq!(
                (lens.focal_length, lens.transmission_coefficient),
                (f, 0.96)
            );
            let (corner, su, sv) = parallelogram(part(&parts, name));
            close(corner + 0.5 * (su + sv), lens.principal_point);
        }
    }

    /// With u and v not perpendicular, each baffle lies in its plane (normal to û, through
    /// C + ½p_u û + ½p_v v̂ plus whole periods) and fills the plane's cut through Dr TIM's
    /// slab {|x·û| ≤ |u|/2, |x·v̂| ≤ |v|/2} (x from C): its corners lie on the slab's faces.
    #[test]
    fn oblique_baffles_fill_the_planes_within_the_slab() {
        let v = DVec3::new(0.6, 0.8, 0.0);
        let clas = Clas {
            span_vector_u: DVec3::new(1.3, 0.0, 0.0),
            span_vector_v: v,
            period_u: 0.3,
            period_v: 0.25,
            ..default_clas()
        };
        let parts = clas.parts(None).unwrap();
        let c = DVec3::new(0.0, 0.0, 5.0);
        let (uh, vh) = (DVec3::X, v);
        let point = 0.15 * uh + 0.125 * vh;
        let mut counts = [0, 0];
        for p in parts.iter().filter(|p| p.name.starts_with("baffle")) {
            let (across, other, half_other, period) = if p.name.starts_with("baffle u") {
                counts[0] += 1;
                (uh, vh, 0.5, 0.3)
            } else {
                counts[1] += 1;
                (vh, uh, 0.65, 0.25)
            };
            let (corner, su, sv) = parallelogram(p);
            for x in [corner, corner + su, corner + sv, corner + su + sv] {
                let r = x - c;
                // In a plane of the family.
                let k = (r - point).dot(across) / period;
                assert!((k - k.round()).abs() < 1e-9, "{}: {k}", p.name);
                // On a face of the slab across `other`, and between the arrays.
                assert!(
                    (r.dot(other).abs() - half_other).abs() < 1e-12,
                    "{}",
                    p.name
                );
                assert!((r.z.abs() - (0.1 - TINY)).abs() < 1e-12);
            }
        }
        // Planes with |x·û| < 0.65: 0.15 + 0.125·0.6 + 0.3k = 0.225 + 0.3k, k = −2 … 1; across v,
        // 0.125 + 0.15·0.6 + 0.25k = 0.215 + 0.25k within ±0.5: k = −2 … 1.
        assert_eq!(counts, [4, 4]);
    }

    #[test]
    fn other_lens_types_and_no_baffles() {
        let clas = Clas {
            lenslet_array_type: LensType::LensHologram,
            channeling_lenses_type: LensType::SemitransparentPlane,
            show_channeling_lens1: true,
            show_baffles: false,
            ..default_clas()
        };
        let parts = clas.parts(None).unwrap();
        let names: Vec<&str> = parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(
            names,
            ["lenslet array 1", "lenslet array 2", "channeling lens 1"]
        );
        let Surface::PhaseHologram(h) = &parts[0].surface else {
            panic!("{:?}", parts[0].surface)
        };
        let Phase::RectangularLensletArray(phase) = &h.phase else {
            panic!("{:?}", h.phase)
        };
        // The lattice about the array's centre, (0.5, 0.5) from its corner.
        assert_eq!(phase.centre, DVec2::splat(0.5));
        assert_eq!((phase.focal_length, phase.period), (0.1, DVec2::splat(0.1)));
        assert_eq!(parts[2].surface, semitransparent_plane());
        let none = Clas {
            lenslet_array_type: LensType::NoLens,
            ..default_clas()
        };
        assert_eq!(none.parts(None).unwrap().len(), 20);
    }

    #[test]
    fn impossible_clas_are_refused_naming_the_key() {
        for (clas, needle) in [
            (
                Clas {
                    span_vector_u: DVec3::new(0.0, 0.0, 2.0),
                    ..default_clas()
                },
                "span_vector_u = [0, 0, 2] has no part perpendicular",
            ),
            (
                Clas {
                    span_vector_v: DVec3::ZERO,
                    ..default_clas()
                },
                "span_vector_v = [0, 0, 0] has no part perpendicular",
            ),
            (
                Clas {
                    span_vector_v: DVec3::new(-2.0, 0.0, 1.0),
                    ..default_clas()
                },
                "span_vector_v = [-2, 0, 1] is parallel to span_vector_u",
            ),
            (
                Clas {
                    f2: -0.09995,
                    ..default_clas()
                },
                "show_baffles: the lenslet arrays are |f1 + f2| =",
            ),
            (
                Clas {
                    period_u: 1e-5,
                    ..default_clas()
                },
                "baffles across u",
            ),
            (
                Clas {
                    lenslet_array_type: LensType::LensHologram,
                    simulate_diffractive_blur: true,
                    ..default_clas()
                },
                "cannot simulate_diffractive_blur",
            ),
            (
                Clas {
                    lenslet_array_type: LensType::LensHologram,
                    span_vector_v: DVec3::new(0.1, 1.0, 0.0),
                    ..default_clas()
                },
                "needs span_vector_u and span_vector_v perpendicular",
            ),
        ] {
            let e = clas.parts(None).unwrap_err();
            assert!(e.contains(needle), "{e}");
        }
        // Without baffles, arrays in one plane are allowed.
        let flat = Clas {
            f2: -0.1,
            show_baffles: false,
            ..default_clas()
        };
        assert_eq!(flat.parts(None).unwrap().len(), 2);
    }
}
