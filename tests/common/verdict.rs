//! Judging `SceneGeometry`'s answers (Embree's f32 BVH with f64 callbacks and f64
//! re-computation) against the brute force (`SceneGeometry::nearest_brute_force`) and against
//! every element primitive's own exact f64 answer: the one set of rules that
//! `tests/embree_vs_reference.rs` (plain objects) and `tests/arrays.rs` (objects repeated in
//! arrays, traced as Embree instances) apply.
//!
//! # What may differ from the brute force, and how that is decided
//!
//! Embree traverses with the ray (and an instance's translation) rounded to f32, is given t_min
//! and t_max rounded to f32, and decides triangle hits in f32; analytic shapes are decided by
//! timbre's exact f64 callbacks on the exact ray (moved by the exact offset in an instance).
//! The answers are compared per *element primitive* (object, element, primitive): element k of
//! an object is its shape moved by its k-th offset (an object in no array has the one element 0
//! at offset 0), a mesh's triangles are its primitives and any other shape is the one primitive
//! 0; its exact answer is the shape's own f64 answer (`Shape::intersect_primitive`) for the ray
//! moved by minus the offset. Only two kinds of difference are excused:
//!
//! * **Marginal primitives.** An element primitive's answer is *robust* unless
//!   * (triangles, decided by Embree in f32) it changes when the ray origin moves by ±δ along
//!     x, y or z, δ = [`PERTURB`] × (1 + |origin| + |offset| + t), with t the hit distance, or
//!     for a miss the distance from the origin to the centre of the shape's bounding box (about
//!     16 f32 roundings of the coordinates involved; Embree rounds both the origin and the
//!     instance translation to f32, so the scale includes both);
//!   * (analytic shapes) it changes when t_min or t_max move by two f32 roundings, or (for a
//!     hit) one of those six moved rays misses the shape's bounding box, so that Embree's f32
//!     traversal might not reach it.
//!
//!   A non-robust primitive may be found or missed. Robustness is worked out lazily, only for
//!   the primitives a verdict depends on, which keeps scenes of hundreds of elements cheap.
//! * **Ties.** Two element primitives at the same exact distance (to [`ANALYTIC_T`] relative;
//!   e.g. overlapping coplanar copies of a disc, or triangles of one mesh meeting at an edge)
//!   may be reported either way. When a triangle is involved, distances within [`TIE`] × (1 + t)
//!   count as a tie too (Embree keeps triangle distances in f32); between analytic shapes,
//!   whose callbacks compare exact f64 distances, they do not.
//!
//! Everything else must match: the reported element primitive must be hit at the reported t (to
//! [`ANALYTIC_T`] relative for analytic shapes, whose t is computed on the exact f64 ray, and
//! [`MESH_T`] for triangles, recomputed in f64 from Embree's f32 hit), no robust primitive may
//! be hit nearer, a robust hit may not be missed, and t must lie in (t_min, t_max). A shadow
//! query must be true exactly when an element primitive of a shadow-throwing object is on the
//! ray, except that non-robust ones may go either way. [`Tally`] counts which verdicts were
//! needed, so that each test can show the excuses are rare and the property is not vacuous.

use std::cell::Cell;

use glam::DVec3;
use timbre::embree::ExactRay;
use timbre::geometry::{Hit, ObjectArray, SceneGeometry, Shape};

use super::AXES;
use super::rays::{Query, box_interval, check_packet, close, interval_ends_do_not_matter};
use super::rng::Rng;

/// Relative size of the ray perturbation that decides robustness (see the module comment).
pub const PERTURB: f64 = 1e-6;
/// Relative distance within which two element primitives' hits are a tie when one of them is a
/// triangle.
pub const TIE: f64 = 1e-5;
/// Relative agreement of t for analytic shapes (exact f64 ray and offset in the callback).
pub const ANALYTIC_T: f64 = 1e-12;
/// Relative agreement of t for triangles (Embree's f32 hit recomputed in f64).
pub const MESH_T: f64 = 1e-9;

/// One copy of one object: element `element` of `object`, its shape moved by `offset`.
#[derive(Debug, Clone, Copy)]
pub struct Element {
    pub object: usize,
    pub element: u32,
    pub offset: DVec3,
}

/// Every (object, element) of a scene, with its offset: an object in an array has one element
/// per offset, any other object the single element 0 at offset 0.
pub fn elements(objects: &[(Shape, bool)], arrays: &[ObjectArray]) -> Vec<Element> {
    let mut out = Vec::new();
    for object in 0..objects.len() {
        match arrays.iter().find(|a| a.objects.contains(&object)) {
            Some(a) => out.extend(a.offsets.iter().enumerate().map(|(k, &offset)| Element {
                object,
                element: k as u32,
                offset,
            })),
            None => out.push(Element {
                object,
                element: 0,
                offset: DVec3::ZERO,
            }),
        }
    }
    out
}

/// One element primitive's exact answer for a query; its robustness is worked out on demand.
#[derive(Debug)]
pub struct Answer {
    pub object: usize,
    pub element: u32,
    pub prim: u32,
    pub offset: DVec3,
    /// The exact distance, if the primitive is hit in (t_min, t_max).
    pub t: Option<f64>,
    pub shadow_throwing: bool,
    robust: Cell<Option<bool>>,
}

/// The exact answers of every element primitive of a scene for one query.
pub struct Answers<'a> {
    objects: &'a [(Shape, bool)],
    pub q: Query,
    pub all: Vec<Answer>,
}

impl<'a> Answers<'a> {
    pub fn new(objects: &'a [(Shape, bool)], elements: &[Element], q: Query) -> Answers<'a> {
        let mut all = Vec::new();
        for e in elements {
            let (shape, shadow_throwing) = &objects[e.object];
            let prims = match shape {
                Shape::TriangleMesh(m) => m.triangles().len() as u32,
                _ => 1,
            };
            let origin = q.origin - e.offset;
            for prim in 0..prims {
                all.push(Answer {
                    object: e.object,
                    element: e.element,
                    prim,
                    offset: e.offset,
                    t: shape.intersect_primitive(prim, origin, q.direction, q.t_min, q.t_max),
                    shadow_throwing: *shadow_throwing,
                    robust: Cell::new(None),
                });
            }
        }
        Answers { objects, q, all }
    }

    pub fn find(&self, object: usize, element: u32, prim: u32) -> Option<&Answer> {
        self.all
            .iter()
            .find(|a| a.object == object && a.element == element && a.prim == prim)
    }

    pub fn is_mesh(&self, object: usize) -> bool {
        matches!(self.objects[object].0, Shape::TriangleMesh(_))
    }

    /// Relative tolerance on t for hits on `object`.
    fn tolerance(&self, object: usize) -> f64 {
        if self.is_mesh(object) {
            MESH_T
        } else {
            ANALYTIC_T
        }
    }

    /// Relative distance within which hits on objects `a` and `b` are a tie.
    fn tie(&self, a: usize, b: usize) -> f64 {
        if self.is_mesh(a) || self.is_mesh(b) {
            TIE
        } else {
            ANALYTIC_T
        }
    }

    /// Whether the answer is robust (see the module comment).
    pub fn robust(&self, a: &Answer) -> bool {
        if let Some(r) = a.robust.get() {
            return r;
        }
        let q = &self.q;
        let shape = &self.objects[a.object].0;
        let origin = q.origin - a.offset;
        let hit_from =
            |o: DVec3| shape.intersect_primitive(a.prim, o, q.direction, q.t_min, q.t_max);
        let distance = a.t.map_or_else(
            || {
                shape
                    .bounds()
                    .map_or(0.0, |(lo, hi)| (0.5 * (lo + hi) - origin).length())
            },
            f64::abs,
        );
        let delta = PERTURB
            * (1.0 + q.origin.abs().max_element() + a.offset.abs().max_element() + distance);
        let shifts = AXES.map(|e| delta * e);
        let robust = match shape {
            // Embree decides triangle hits in f32: the answer must survive moving the ray.
            Shape::TriangleMesh(_) => shifts
                .iter()
                .all(|&s| hit_from(origin + s).is_some() == a.t.is_some()),
            // Analytic shapes are decided exactly in f64, given t_min and t_max rounded to f32,
            // once Embree's f32 traversal reaches their bounding box.
            _ => {
                let box_reached = match (a.t, shape.bounds()) {
                    (Some(_), Some((lo, hi))) => shifts.iter().all(|&s| {
                        box_interval(origin + s, q.direction, lo, hi)
                            .is_some_and(|(t0, t1)| t0 < q.t_max && t1 > q.t_min)
                    }),
                    _ => true,
                };
                box_reached && interval_ends_do_not_matter(shape, origin, q)
            }
        };
        a.robust.set(Some(robust));
        robust
    }
}

/// How an answer was accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Same (object, element, prim) and t as the brute force, or both miss.
    Same,
    /// A different element primitive at the brute force's distance (within the tolerances).
    EqualTie,
    /// A different element primitive, one of them a triangle, within `TIE` of the brute force.
    NearTie,
    /// The difference is due to a non-robust element primitive.
    Marginal,
}

/// Checks a nearest-hit answer against the element primitives' answers and the brute force.
pub fn check_nearest(
    answers: &Answers,
    brute: Option<Hit>,
    got: Option<Hit>,
) -> Result<Verdict, String> {
    let q = &answers.q;
    // The brute force is the nearest of the element primitives' own answers.
    let nearest = answers
        .all
        .iter()
        .filter_map(|a| a.t)
        .min_by(f64::total_cmp);
    let consistent = brute.map(|b| b.t) == nearest
        && brute.is_none_or(|b| {
            answers
                .find(b.object, b.element, b.prim)
                .is_some_and(|a| a.t == Some(b.t))
        });
    if !consistent {
        return Err(format!(
            "brute force {brute:?} is not the nearest element primitive ({nearest:?})"
        ));
    }
    let Some(h) = got else {
        return match answers
            .all
            .iter()
            .find(|a| a.t.is_some() && answers.robust(a))
        {
            Some(a) => Err(format!("missed a robust hit {a:?} (brute force {brute:?})")),
            None if brute.is_none() => Ok(Verdict::Same),
            None => Ok(Verdict::Marginal),
        };
    };
    if !(h.t > q.t_min && h.t < q.t_max) {
        return Err(format!("hit {h:?} outside ({}, {})", q.t_min, q.t_max));
    }
    // The reported element primitive really is hit at the reported distance, or is marginal.
    let Some(own) = answers.find(h.object, h.element, h.prim) else {
        return Err(format!("hit {h:?} names no element primitive"));
    };
    let tolerance = answers.tolerance(h.object);
    let exact = own.t.is_some_and(|t| close(t, h.t, tolerance));
    if !exact && answers.robust(own) {
        return Err(format!(
            "hit {h:?}, but the element primitive's exact answer is {own:?} (brute force {brute:?})"
        ));
    }
    if let Some(a) = answers.all.iter().find(|a| {
        a.t.is_some_and(|t| t < h.t && !close(t, h.t, answers.tie(a.object, h.object)))
            && answers.robust(a)
    }) {
        return Err(format!("hit {h:?} behind a robust hit {a:?}"));
    }
    let b = brute.expect("a robust miss of everything was excluded above");
    let same_primitive = (b.object, b.element, b.prim) == (h.object, h.element, h.prim);
    let equal = tolerance.max(answers.tolerance(b.object));
    Ok(if same_primitive && close(b.t, h.t, tolerance) {
        Verdict::Same
    } else if close(b.t, h.t, equal) {
        Verdict::EqualTie
    } else if close(b.t, h.t, answers.tie(b.object, h.object)) {
        Verdict::NearTie
    } else if !exact
        || answers
            .find(b.object, b.element, b.prim)
            .is_some_and(|a| !answers.robust(a))
    {
        Verdict::Marginal
    } else {
        return Err(format!("hit {h:?} but brute force {b:?}"));
    })
}

/// Checks a shadow query: true exactly when an element of a shadow-throwing object lies on the
/// ray, except that non-robust element primitives of shadow-throwing objects may go either way.
pub fn check_shadowed(answers: &Answers, got: bool) -> Result<Verdict, String> {
    let throwers = || answers.all.iter().filter(|a| a.shadow_throwing);
    let robust_hit = throwers().any(|a| a.t.is_some() && answers.robust(a));
    if robust_hit {
        return if got {
            Ok(Verdict::Same)
        } else {
            let a = throwers().find(|a| a.t.is_some() && answers.robust(a));
            Err(format!(
                "an element of a shadow-throwing object robustly on the ray ({a:?}), but not \
                 shadowed"
            ))
        };
    }
    let any_hit = throwers().any(|a| a.t.is_some());
    if got == any_hit {
        return Ok(Verdict::Same);
    }
    if throwers().any(|a| !answers.robust(a)) {
        Ok(Verdict::Marginal)
    } else if got {
        Err("shadowed, but no element of a shadow-throwing object is on the ray".into())
    } else {
        unreachable!("a hit of a thrower that is not robust is marginal")
    }
}

/// Tally of verdicts over a run, indexed by `Verdict as usize`.
#[derive(Debug, Default)]
pub struct Tally {
    pub nearest: [usize; 4],
    pub shadowed: [usize; 4],
    pub packet: [usize; 4],
    /// Packet lanes that differ from the single-ray answer.
    pub packet_differs: usize,
    /// Single rays that hit something.
    pub hits: usize,
    /// Shadow rays that were shadowed.
    pub shadowed_rays: usize,
}

impl Tally {
    pub fn add(&mut self, t: &Tally) {
        for k in 0..4 {
            self.nearest[k] += t.nearest[k];
            self.shadowed[k] += t.shadowed[k];
            self.packet[k] += t.packet[k];
        }
        self.packet_differs += t.packet_differs;
        self.hits += t.hits;
        self.shadowed_rays += t.shadowed_rays;
    }
}

/// Runs every check on a built scene: `rays` single rays (`nearest` and `shadowed`) and
/// `packets` packets of up to 8 (`nearest8` or `nearest_packet`, each lane also against
/// `nearest`, and `shadowed8`), their queries
/// drawn by `draw` from `rng`. `observe` sees each single ray's answers and hit, for counts of
/// a test's own.
#[allow(clippy::too_many_arguments)]
pub fn check_queries(
    scene: &SceneGeometry,
    objects: &[(Shape, bool)],
    elements: &[Element],
    rng: &mut Rng,
    rays: usize,
    packets: usize,
    mut draw: impl FnMut(&mut Rng) -> Query,
    mut observe: impl FnMut(&Answers, Option<Hit>),
) -> Result<Tally, String> {
    let mut tally = Tally::default();
    for _ in 0..rays {
        let q = draw(rng);
        let answers = Answers::new(objects, elements, q);
        let brute = scene.nearest_brute_force(q.origin, q.direction, q.t_min, q.t_max);
        let got = scene.nearest(q.origin, q.direction, q.t_min, q.t_max);
        let v = check_nearest(&answers, brute, got).map_err(|e| format!("nearest: {e}\n{q:?}"))?;
        tally.nearest[v as usize] += 1;
        tally.hits += usize::from(got.is_some());
        let shadowed = scene.shadowed(q.origin, q.direction, q.t_min, q.t_max);
        tally.shadowed_rays += usize::from(shadowed);
        let v = check_shadowed(&answers, shadowed)
            .map_err(|e| format!("shadowed ({shadowed}): {e}\n{q:?}"))?;
        tally.shadowed[v as usize] += 1;
        observe(&answers, got);
    }
    for _ in 0..packets {
        // A packet from one origin or from origins about it: coherent (around an aim point)
        // or scattered.
        let base = draw(rng);
        tally.packet_differs += check_packet(scene, base, rng, |q, lane, single| {
            let answers = Answers::new(objects, elements, q);
            let brute = scene.nearest_brute_force(q.origin, q.direction, q.t_min, q.t_max);
            let v = check_nearest(&answers, brute, lane)
                .map_err(|e| format!("packet lane (single ray: {single:?}): {e}\n{q:?}"))?;
            tally.packet[v as usize] += 1;
            Ok(())
        })?;
        // Up to 8 shadow rays as one packet: each lane against the brute-force answers.
        let queries: Vec<Query> = (0..1 + rng.index(8)).map(|_| draw(rng)).collect();
        let segments: Vec<_> = queries
            .iter()
            .map(|q| {
                let ray = ExactRay {
                    origin: q.origin,
                    direction: q.direction,
                };
                (ray, q.t_min, q.t_max)
            })
            .collect();
        let lanes = scene.shadowed8(&segments);
        if lanes[queries.len()..].iter().any(|&b| b) {
            return Err(format!(
                "shadowed8 answered lanes beyond its rays: {lanes:?}"
            ));
        }
        for (&q, &shadowed) in queries.iter().zip(&lanes) {
            let answers = Answers::new(objects, elements, q);
            let v = check_shadowed(&answers, shadowed)
                .map_err(|e| format!("shadowed8 lane ({shadowed}): {e}\n{q:?}"))?;
            tally.shadowed[v as usize] += 1;
        }
    }
    Ok(tally)
}
