//! What the shapes around an axis share (cone, paraboloid, elliptic cylinder, spherical cap):
//! their own coordinates (x along û, y along v̂, z along the axis, from a point of the axis),
//! lines re-origined in them, and the cut of a line's span to the slab between end planes.

use glam::DVec3;

use super::Span;
use crate::math::{Frame, nearest_in};

/// A point of an axis, the unit axis (the frame's w) and unit vectors û, v̂ across it with
/// û × v̂ = axis (the frame's u and v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Axis {
    pub origin: DVec3,
    pub frame: Frame,
}

impl Axis {
    /// From `origin` along the unit vector `axis`, with û along the part of `u` across it, or
    /// without `u` the disc axes for a normal along it (as a cylinder's surface coordinates).
    pub fn new(origin: DVec3, axis: DVec3, u: Option<DVec3>) -> Axis {
        let frame = match u {
            Some(u) => Frame::from_normal_and_u(axis, u),
            None => Frame::from_normal(axis),
        };
        Axis { origin, frame }
    }

    /// The coordinates (x, y, z) of the point `p`.
    pub fn local(&self, p: DVec3) -> DVec3 {
        self.local_vector(p - self.origin)
    }

    /// The components (along û, v̂, axis) of the vector `v`.
    pub fn local_vector(&self, v: DVec3) -> DVec3 {
        let f = &self.frame;
        DVec3::new(v.dot(f.u), v.dot(f.v), v.dot(f.w))
    }

    /// The point with coordinates `c`.
    pub fn world(&self, c: DVec3) -> DVec3 {
        self.origin + self.world_vector(c)
    }

    /// The vector with components `c`.
    pub fn world_vector(&self, c: DVec3) -> DVec3 {
        c.x * self.frame.u + c.y * self.frame.v + c.z * self.frame.w
    }

    /// The line `origin + t direction` in these coordinates, re-origined at its point nearest
    /// the axis's origin, so that quadratics along it do not subtract the large, nearly equal
    /// terms of a far-away origin.
    pub fn line(&self, origin: DVec3, direction: DVec3) -> Line {
        let (q, d) = (self.local(origin), self.local_vector(direction));
        let shift = -q.dot(d) / d.length_squared();
        let shift = if shift.is_finite() { shift } else { 0.0 };
        Line {
            shift,
            q: q + shift * d,
            d,
        }
    }

    /// Axis-aligned bounds of the ellipse across the axis at height `z`, with semi-axes `a`
    /// along û and `b` along v̂: its centre ± (a² û_i² + b² v̂_i²)^½ along each world axis i.
    pub fn ellipse_bounds(&self, z: f64, a: f64, b: f64) -> (DVec3, DVec3) {
        let (u, v) = (self.frame.u, self.frame.v);
        let e = (a * a * u * u + b * b * v * v).sqrt();
        let centre = self.world(DVec3::new(0.0, 0.0, z));
        (centre - e, centre + e)
    }
}

/// A line in an [`Axis`]'s coordinates: the points q + s d, where s = t − `shift` for the
/// line's distance t in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Line {
    pub shift: f64,
    pub q: DVec3,
    pub d: DVec3,
}

impl Line {
    /// The span `inside` (in s, of the line inside an unbounded solid) cut to the slab
    /// between the planes z = `lower` and z = `upper` across the axis (each with the part it
    /// is; `None`: no plane on that side), as distances t in the world.
    pub fn cut(
        &self,
        inside: Span,
        lower: Option<(f64, u32)>,
        upper: Option<(f64, u32)>,
    ) -> Option<Span> {
        let mut span = inside;
        for (plane, keep_below) in [(lower, false), (upper, true)] {
            let Some((z, part)) = plane else { continue };
            if self.d.z == 0.0 {
                let outside = if keep_below {
                    self.q.z > z
                } else {
                    self.q.z < z
                };
                if outside {
                    return None;
                }
                continue;
            }
            let s = (z - self.q.z) / self.d.z;
            if (self.d.z > 0.0) == keep_below {
                if s < span.exit.0 {
                    span.exit = (s, part);
                }
            } else if s > span.enter.0 {
                span.enter = (s, part);
            }
        }
        (span.enter.0 < span.exit.0).then_some(Span {
            enter: (span.enter.0 + self.shift, span.enter.1),
            exit: (span.exit.0 + self.shift, span.exit.1),
        })
    }

    /// The nearest hit in (t_min, t_max) of a shape round the axis whose side surface the line
    /// crosses at the ends of `inside` (part 0), with its caps on the planes `lower` (if any;
    /// else the side begins at z = 0) and `upper`: of the side alone between them if `open`,
    /// else of the closed solid ([`Self::cut`]).
    pub fn nearest_hit(
        &self,
        inside: Span,
        lower: Option<(f64, u32)>,
        upper: (f64, u32),
        open: bool,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        if open {
            let from = lower.map_or(0.0, |l| l.0);
            let t = self.nearest_between(inside, from, upper.0, t_min, t_max)?;
            Some((t, 0))
        } else {
            self.cut(inside, lower, Some(upper))?.nearest(t_min, t_max)
        }
    }

    /// The nearest t in (t_min, t_max) among the finite ends of `inside` (in s, of the line
    /// inside an unbounded solid: where it crosses the mantle) with `lower` ≤ z ≤ `upper`.
    pub fn nearest_between(
        &self,
        inside: Span,
        lower: f64,
        upper: f64,
        t_min: f64,
        t_max: f64,
    ) -> Option<f64> {
        let crossings = [inside.enter, inside.exit]
            .into_iter()
            .filter(|&(s, part)| {
                part != Span::NO_PART && (lower..=upper).contains(&(self.q.z + s * self.d.z))
            })
            .map(|(s, _)| s + self.shift);
        nearest_in(crossings, t_min, t_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_span_is_cut_to_the_slab_and_shifted_back() {
        // The line (0, 0, −5) + s (0, 0, 1), everywhere inside (a line along an infinite
        // cylinder's axis), cut to 0 ≤ z ≤ 2, with a shift of 10.
        let line = Line {
            shift: 10.0,
            q: DVec3::new(0.0, 0.0, -5.0),
            d: DVec3::Z,
        };
        let all = Span {
            enter: (f64::NEG_INFINITY, Span::NO_PART),
            exit: (f64::INFINITY, Span::NO_PART),
        };
        let cut = line.cut(all, Some((0.0, 1)), Some((2.0, 2))).unwrap();
        assert_eq!((cut.enter, cut.exit), ((15.0, 1), (17.0, 2)));
        // Going the other way the planes swap roles.
        let back = Line {
            d: DVec3::NEG_Z,
            q: DVec3::new(0.0, 0.0, 5.0),
            ..line
        };
        let cut = back.cut(all, Some((0.0, 1)), Some((2.0, 2))).unwrap();
        assert_eq!((cut.enter, cut.exit), ((13.0, 2), (15.0, 1)));
        // Across the axis: inside the slab or not at all.
        let across = Line {
            d: DVec3::X,
            ..line
        };
        assert_eq!(across.cut(all, Some((0.0, 1)), Some((2.0, 2))), None);
        assert_eq!(
            line.nearest_between(
                Span {
                    enter: (1.0, 0),
                    exit: (6.0, 0)
                },
                0.0,
                2.0,
                0.0,
                100.0
            ),
            Some(16.0)
        );
    }
}
