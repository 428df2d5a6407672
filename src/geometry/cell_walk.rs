//! The walk along a ray through the cells of a solid made cell by cell (a lenslet array, a
//! refractive view rotator): a lattice of cells (i, j), each holding its own piece of glass,
//! inside a box. Where the pieces of neighbouring cells are both glass at their common wall
//! there is no surface (the solid is one piece of glass); where one is glass and the other not,
//! the wall bounds it, and so do the box's faces.
//!
//! The cell a point is in is given by two lattice coordinates s and t (cell (i, j) covers
//! |s − i| ≤ ½, |t − j| ≤ ½). Along the ray each is a linear-fractional function of the ray
//! parameter λ, monotonic on the stretch inside the box ([`LineCoordinate`]), so the ray
//! crosses the cells one after another. Within a cell the ray is cut at its crossings of the
//! cell's surfaces; each stretch is classified inside or outside the glass at its midpoint,
//! and the first change of side after t_min is the hit, so that an origin on the surface is
//! never misjudged.

use glam::DVec3;

/// A lattice coordinate along the line origin + λ direction, s(λ) = (α + β λ)/(γ + δ λ):
/// linear (γ = 1, δ = 0) for a lattice of parallel planes, fractional for a fan of planes
/// through a point. The walk needs γ + δ λ of one sign on the stretch walked.
#[derive(Debug, Clone, Copy)]
pub(super) struct LineCoordinate {
    alpha: f64,
    beta: f64,
    gamma: f64,
    delta: f64,
}

impl LineCoordinate {
    /// s(λ) = s₀ + λ ds.
    pub(super) fn linear(s0: f64, ds: f64) -> LineCoordinate {
        LineCoordinate {
            alpha: s0,
            beta: ds,
            gamma: 1.0,
            delta: 0.0,
        }
    }

    /// s(λ) = (α + β λ)/(γ + δ λ).
    pub(super) fn fractional(alpha: f64, beta: f64, gamma: f64, delta: f64) -> LineCoordinate {
        LineCoordinate {
            alpha,
            beta,
            gamma,
            delta,
        }
    }

    fn at(&self, l: f64) -> f64 {
        (self.alpha + self.beta * l) / (self.gamma + self.delta * l)
    }

    /// The sign of ds/dλ (+1, −1, or 0 where s is constant).
    pub(super) fn sign(&self) -> f64 {
        let slope = self.beta * self.gamma - self.alpha * self.delta;
        if slope == 0.0 { 0.0 } else { slope.signum() }
    }

    /// Where s, moving towards σ from `from`, reaches σ (∞ if it never does). Linear, that is
    /// where the line meets the plane s = σ. Fractional, the equation also has a root beyond
    /// the pole γ + δ λ = 0 (behind the eye of a fan), and a line of constant s puts its one
    /// root at the pole: only a root after `from` counts, and where rounding has put s(from)
    /// at or past σ already, it is reached at once. `sign` is [`Self::sign`], which the walk
    /// holds.
    fn reach(&self, sigma: f64, from: f64, sign: f64) -> f64 {
        let l = (sigma * self.gamma - self.alpha) / (self.beta - sigma * self.delta);
        if self.delta == 0.0 {
            return l;
        }
        if (self.at(from) - sigma) * sign >= 0.0 {
            from
        } else if l > from {
            l
        } else {
            f64::INFINITY
        }
    }
}

/// What bounds a stretch of the ray: one of the cell's own surfaces, a wall across s (0) or t
/// (1), a face of the box (its number), or nothing (the end of the search).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Bound {
    Surface(u32),
    Wall(usize),
    Face(usize),
    None,
}

/// The stretch [lo, hi] of the ray inside the box and what it enters and leaves by.
pub(super) struct Stretch {
    lo: f64,
    hi: f64,
    enter: Bound,
    leave: Bound,
}

/// The most crossings of a cell's own surfaces a line can have.
const MAX_CROSSINGS: usize = 4;

/// A solid made cell by cell.
pub(super) trait CellSolid {
    /// What the walk needs of a cell to find its crossings and classify points.
    type Cell;

    fn cell(&self, i: i64, j: i64) -> Self::Cell;

    /// Each crossing (λ, surface) of the line with the cell's own surfaces, at most
    /// [`MAX_CROSSINGS`] of them.
    fn crossings(
        &self,
        cell: &Self::Cell,
        origin: DVec3,
        direction: DVec3,
        crossing: impl FnMut(f64, u32),
    );

    /// Whether `x`, in the cell, is in its glass.
    fn inside(&self, cell: &Self::Cell, x: DVec3) -> bool;

    /// The part hit at a change of side in cell (i, j) at `bound`, `leaving` the glass or
    /// entering it, along `direction`; `signs` are those of ds/dλ and dt/dλ. A wall is crossed
    /// on the way into cell (i, j), a face on the way into or out of the box.
    fn hit_part(
        &self,
        i: i64,
        j: i64,
        bound: Bound,
        leaving: bool,
        direction: DVec3,
        signs: [f64; 2],
    ) -> u32;
}

/// The stretch of the line in the box given by three slabs (p + λ dp ∈ [a, b], entered and
/// left by the slab's bound), cut to (t_min, t_max); `None` if it is empty.
pub(super) fn clip(
    slabs: [(f64, f64, [f64; 2], Bound); 3],
    t_min: f64,
    t_max: f64,
) -> Option<Stretch> {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut enter, mut leave) = (Bound::None, Bound::None);
    for (p, dp, [a, b], bound) in slabs {
        if dp == 0.0 {
            if p < a || p > b {
                return None;
            }
            continue;
        }
        let (l1, l2) = ((a - p) / dp, (b - p) / dp);
        if l1.min(l2) > lo {
            (lo, enter) = (l1.min(l2), bound);
        }
        if l1.max(l2) < hi {
            (hi, leave) = (l1.max(l2), bound);
        }
    }
    if lo.is_nan() || hi.is_nan() || lo >= hi || hi <= t_min || lo >= t_max {
        return None;
    }
    if hi > t_max {
        (hi, leave) = (t_max, Bound::None);
    }
    Some(Stretch {
        lo,
        hi,
        enter,
        leave,
    })
}

/// The first change of side of the glass after t_min on the stretch, with the part hit there.
pub(super) fn walk<S: CellSolid>(
    solid: &S,
    origin: DVec3,
    direction: DVec3,
    t_min: f64,
    stretch: Stretch,
    [s, t]: [LineCoordinate; 2],
) -> Option<(f64, u32)> {
    let Stretch {
        lo,
        hi,
        enter,
        leave,
    } = stretch;
    let signs = [s.sign(), t.sign()];
    let at = |l: f64| origin + l * direction;
    // The cell the line is in at the start (on a wall, the one it moves into), and where it
    // crosses the cell's next wall across s and across t.
    let cell = |p: f64, sign: f64| {
        let c = if sign >= 0.0 {
            (p + 0.5).floor()
        } else {
            (p - 0.5).ceil()
        };
        (c as i64).clamp(i64::MIN / 2, i64::MAX / 2)
    };
    let (mut i, mut j) = (cell(s.at(lo), signs[0]), cell(t.at(lo), signs[1]));
    let next = |c: i64, coordinate: &LineCoordinate, sign: f64, from: f64| match sign {
        sign if sign > 0.0 => coordinate.reach(c as f64 + 0.5, from, sign),
        sign if sign < 0.0 => coordinate.reach(c as f64 - 0.5, from, sign),
        _ => f64::INFINITY,
    };
    let mut inside = false;
    let mut from = (lo, enter);
    // The stretch's start, the crossings of the cell's surfaces and its end.
    let mut events = [(0.0, Bound::None); MAX_CROSSINGS + 2];
    loop {
        let (ls, lt) = (next(i, &s, signs[0], from.0), next(j, &t, signs[1], from.0));
        let (end, wall) = if ls.min(lt) < hi {
            if ls <= lt {
                (ls, Bound::Wall(0))
            } else {
                (lt, Bound::Wall(1))
            }
        } else {
            (hi, leave)
        };
        let piece = solid.cell(i, j);
        events[0] = from;
        let mut count = 1;
        solid.crossings(&piece, origin, direction, |l, surface| {
            if l > from.0 && l < end && count <= MAX_CROSSINGS {
                events[count] = (l, Bound::Surface(surface));
                count += 1;
            }
        });
        events[1..count].sort_by(|a, b| a.0.total_cmp(&b.0));
        events[count] = (end, wall);
        for pair in events[..=count].windows(2) {
            let ((l, bound), (l_next, _)) = (pair[0], pair[1]);
            // A stretch of no length (through a corner, a crossing on a wall) has no side.
            if l_next <= l {
                continue;
            }
            let now = solid.inside(&piece, at(0.5 * (l + l_next)));
            if now != inside && l > t_min {
                return Some((l, solid.hit_part(i, j, bound, inside, direction, signs)));
            }
            inside = now;
        }
        if end >= hi {
            // Leaving the box: through its boundary if the glass reaches it.
            return (inside && leave != Bound::None && hi > t_min)
                .then(|| (hi, solid.hit_part(i, j, leave, true, direction, signs)));
        }
        match wall {
            Bound::Wall(0) => i += signs[0] as i64,
            _ => j += signs[1] as i64,
        }
        from = (end, wall);
    }
}
