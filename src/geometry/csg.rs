//! Constructive solid geometry: the union, intersection, difference and inverse of solids,
//! nested to any depth, evaluated exactly along each ray as the list of spans of the line
//! inside the result (no sampling).
//!
//! The pieces (*leaves*) are convex solids ([`ConvexSolid`]: spheres, capped cylinders,
//! polyhedra, half-spaces behind planes, ...). A difference A − B − C is A ∩ ¬B ∩ ¬C and an
//! inverse is the complement, so by De Morgan's laws every operation becomes a tree of unions
//! and intersections whose leaves are each taken as they are or complemented. A boundary
//! point of the result on leaf L is where the line crosses L's surface, and the result's
//! outward normal there is L's, reversed if L is complemented; the frame turns half a turn
//! about u (u, −v, −w), so it stays right-handed.
//!
//! A hit's part says which leaf, and which part of the leaf, it is on: leaf index × 2¹⁶ + the
//! leaf's own part.

use glam::{DVec2, DVec3};
use serde::Deserialize;
use smallvec::SmallVec;

use super::{AnalyticShape, ConvexSolid, GeometryError, Shape, ShapeKeys, Span};
use crate::math::Frame;

/// What a CSG shape does with its members.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CsgOperation {
    /// Inside any member.
    Union,
    /// Inside every member.
    Intersection,
    /// Inside the first member and outside all the others.
    Difference,
    /// Outside the single member.
    Inverse,
}

impl CsgOperation {
    /// The name scene files use.
    pub fn name(self) -> &'static str {
        match self {
            CsgOperation::Union => "union",
            CsgOperation::Intersection => "intersection",
            CsgOperation::Difference => "difference",
            CsgOperation::Inverse => "inverse",
        }
    }
}

/// The most leaves a CSG shape may have (the part number holds the leaf index in 16 bits).
pub const MAX_LEAVES: usize = 1 << 16;

/// Unions and intersections of leaves (each complemented or not, see [`Csg`]).
#[derive(Debug, Clone, PartialEq)]
enum Node {
    Leaf(usize),
    Union(Vec<Node>),
    Intersection(Vec<Node>),
}

/// The spans of a line inside a solid, in order along the line, disjoint and not touching.
type Spans = SmallVec<[Span; 4]>;

#[derive(Debug, Clone, PartialEq)]
pub struct Csg {
    operation: CsgOperation,
    /// What the shape is called in reports: the operation's name, or the scene-file type of a
    /// shape built from CSG (a tube, a lens).
    kind: &'static str,
    /// Convex solids.
    leaves: Vec<Shape>,
    /// Whether each leaf enters the tree complemented.
    complemented: Vec<bool>,
    root: Node,
    bounds: Option<(DVec3, DVec3)>,
}

impl Csg {
    /// `operation` applied to `members` (exactly one for an inverse, at least two otherwise),
    /// each a solid: a convex solid or another CSG shape.
    pub fn new(operation: CsgOperation, members: Vec<Shape>) -> Result<Csg, GeometryError> {
        let count_ok = match operation {
            CsgOperation::Inverse => members.len() == 1,
            _ => members.len() >= 2,
        };
        if !count_ok {
            let needed = match operation {
                CsgOperation::Inverse => "exactly one member",
                _ => "at least two members",
            };
            return Err(GeometryError::Degenerate(format!(
                "a {} needs {needed}, got {}",
                operation.name(),
                members.len()
            )));
        }
        let mut csg = Csg {
            operation,
            kind: operation.name(),
            leaves: Vec::new(),
            complemented: Vec::new(),
            root: Node::Union(Vec::new()),
            bounds: None,
        };
        let mut nodes = Vec::with_capacity(members.len());
        for (i, member) in members.into_iter().enumerate() {
            let complement = match operation {
                CsgOperation::Union | CsgOperation::Intersection => false,
                CsgOperation::Difference => i > 0,
                CsgOperation::Inverse => true,
            };
            nodes.push(csg.graft(member, complement, i)?);
        }
        csg.root = match operation {
            CsgOperation::Union => Node::Union(nodes),
            CsgOperation::Intersection | CsgOperation::Difference => Node::Intersection(nodes),
            CsgOperation::Inverse => nodes.pop().expect("one member"),
        };
        csg.bounds = csg.node_bounds(&csg.root);
        if let Some((lo, hi)) = csg.bounds
            && lo.cmpgt(hi).any()
        {
            return Err(GeometryError::Degenerate(format!(
                "the {} is empty: its members do not overlap",
                operation.name()
            )));
        }
        Ok(csg)
    }

    /// Adds member `index`'s leaves and returns its node (complemented if `complement`).
    fn graft(
        &mut self,
        member: Shape,
        complement: bool,
        index: usize,
    ) -> Result<Node, GeometryError> {
        let node = match member {
            Shape::Csg(inner) => {
                let base = self.leaves.len();
                self.leaves.extend(inner.leaves);
                self.complemented.extend(inner.complemented);
                inner.root.shifted(base)
            }
            leaf if leaf.is_solid() => {
                self.leaves.push(leaf);
                self.complemented.push(false);
                Node::Leaf(self.leaves.len() - 1)
            }
            other => {
                return Err(GeometryError::Degenerate(format!(
                    "member {} of the {} ({}) does not enclose a solid \
                     (constructive solid geometry combines closed solids and the half-spaces \
                     behind planes)",
                    index + 1,
                    self.operation.name(),
                    other.kind()
                )));
            }
        };
        if self.leaves.len() > MAX_LEAVES {
            return Err(GeometryError::Degenerate(format!(
                "the {} has more than {MAX_LEAVES} pieces",
                self.operation.name()
            )));
        }
        Ok(if complement {
            node.complement(&mut self.complemented)
        } else {
            node
        })
    }

    pub fn operation(&self) -> CsgOperation {
        self.operation
    }

    /// The operation's name, or the kind given by [`Self::called`].
    pub fn kind(&self) -> &'static str {
        self.kind
    }

    /// The same shape, called `kind` in reports (a shape built from CSG).
    pub fn called(mut self, kind: &'static str) -> Csg {
        self.kind = kind;
        self
    }

    /// The convex solids the shape is built from.
    pub fn leaves(&self) -> &[Shape] {
        &self.leaves
    }

    /// The same tree with every leaf replaced by `f(leaf)` (which must stay a convex solid):
    /// how a transform reaches the leaves.
    pub fn map_leaves(
        &self,
        mut f: impl FnMut(&Shape) -> Result<Shape, GeometryError>,
    ) -> Result<Csg, GeometryError> {
        let leaves = self
            .leaves
            .iter()
            .map(&mut f)
            .collect::<Result<Vec<_>, _>>()?;
        let mut csg = Csg {
            leaves,
            ..self.clone()
        };
        csg.bounds = csg.node_bounds(&csg.root);
        Ok(csg)
    }

    /// Whether `p` is inside the solid (points on its surface may go either way).
    pub fn contains(&self, p: DVec3) -> bool {
        self.node_contains(&self.root, p)
    }

    fn node_contains(&self, node: &Node, p: DVec3) -> bool {
        match node {
            Node::Leaf(i) => self.solid(*i).contains(p) != self.complemented[*i],
            Node::Union(nodes) => nodes.iter().any(|n| self.node_contains(n, p)),
            Node::Intersection(nodes) => nodes.iter().all(|n| self.node_contains(n, p)),
        }
    }

    fn solid(&self, leaf: usize) -> &dyn ConvexSolid {
        self.leaves[leaf]
            .analytic_solid()
            .expect("CSG leaves are convex solids")
    }

    /// Bounds of a node; `None` if unbounded (a complemented leaf, a half-space).
    fn node_bounds(&self, node: &Node) -> Option<(DVec3, DVec3)> {
        match node {
            Node::Leaf(i) if self.complemented[*i] => None,
            Node::Leaf(i) => self.leaves[*i].bounds(),
            Node::Union(nodes) => {
                nodes
                    .iter()
                    .try_fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), n| {
                        let (a, b) = self.node_bounds(n)?;
                        Some((lo.min(a), hi.max(b)))
                    })
            }
            Node::Intersection(nodes) => nodes
                .iter()
                .filter_map(|n| self.node_bounds(n))
                .reduce(|(lo, hi), (a, b)| (lo.max(a), hi.min(b))),
        }
    }

    /// The spans of the line `origin + t direction` inside a node.
    fn spans(&self, node: &Node, origin: DVec3, direction: DVec3) -> Spans {
        match node {
            Node::Leaf(i) => {
                let tag = |(t, part): (f64, u32)| {
                    let part = if part == Span::NO_PART {
                        part
                    } else {
                        ((*i as u32) << 16) | part
                    };
                    (t, part)
                };
                let chord = self.solid(*i).chord(origin, direction).map(|s| Span {
                    enter: tag(s.enter),
                    exit: tag(s.exit),
                });
                let spans: Spans = chord.into_iter().collect();
                if self.complemented[*i] {
                    complement(&spans)
                } else {
                    spans
                }
            }
            Node::Union(nodes) => union(
                nodes
                    .iter()
                    .flat_map(|n| self.spans(n, origin, direction))
                    .collect(),
            ),
            Node::Intersection(nodes) => {
                let mut nodes = nodes.iter();
                let first = nodes.next().expect("intersections have members");
                let mut all = self.spans(first, origin, direction);
                for n in nodes {
                    if all.is_empty() {
                        break;
                    }
                    all = intersection(&all, &self.spans(n, origin, direction));
                }
                all
            }
        }
    }

    fn leaf_and_part(part: u32) -> (usize, u32) {
        ((part >> 16) as usize, part & 0xffff)
    }
}

impl Node {
    fn shifted(self, base: usize) -> Node {
        match self {
            Node::Leaf(i) => Node::Leaf(i + base),
            Node::Union(n) => Node::Union(n.into_iter().map(|n| n.shifted(base)).collect()),
            Node::Intersection(n) => {
                Node::Intersection(n.into_iter().map(|n| n.shifted(base)).collect())
            }
        }
    }

    /// The complement by De Morgan's laws: unions and intersections swap, leaves flip.
    fn complement(self, complemented: &mut [bool]) -> Node {
        match self {
            Node::Leaf(i) => {
                complemented[i] = !complemented[i];
                Node::Leaf(i)
            }
            Node::Union(n) => {
                Node::Intersection(n.into_iter().map(|n| n.complement(complemented)).collect())
            }
            Node::Intersection(n) => {
                Node::Union(n.into_iter().map(|n| n.complement(complemented)).collect())
            }
        }
    }
}

/// The complement of ordered spans: the gaps between them, and beyond them to ±∞.
fn complement(spans: &[Span]) -> Spans {
    let mut out = Spans::new();
    let mut from = (f64::NEG_INFINITY, Span::NO_PART);
    for s in spans {
        if s.enter.0 > from.0 {
            out.push(Span {
                enter: from,
                exit: s.enter,
            });
        }
        from = s.exit;
    }
    if from.0 < f64::INFINITY {
        out.push(Span {
            enter: from,
            exit: (f64::INFINITY, Span::NO_PART),
        });
    }
    out
}

/// The union of spans in any order, ordered; spans that overlap or touch become one (two solids
/// glued face to face have no surface between them).
fn union(mut spans: Spans) -> Spans {
    spans.sort_unstable_by(|x, y| x.enter.0.total_cmp(&y.enter.0));
    let mut out = Spans::new();
    for s in spans {
        match out.last_mut() {
            Some(last) if s.enter.0 <= last.exit.0 => {
                if s.exit.0 > last.exit.0 {
                    last.exit = s.exit;
                }
            }
            _ => out.push(s),
        }
    }
    out
}

/// The intersection of two ordered span lists (spans that only touch share nothing).
fn intersection(a: &[Span], b: &[Span]) -> Spans {
    let mut out = Spans::new();
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        let (x, y) = (a[i], b[j]);
        let enter = if x.enter.0 >= y.enter.0 {
            x.enter
        } else {
            y.enter
        };
        let exit = if x.exit.0 <= y.exit.0 { x.exit } else { y.exit };
        if enter.0 < exit.0 {
            out.push(Span { enter, exit });
        }
        if x.exit.0 <= y.exit.0 {
            i += 1;
        } else {
            j += 1;
        }
    }
    out
}

impl AnalyticShape for Csg {
    /// The first crossing of the result's surface in (t_min, t_max).
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        self.spans(&self.root, origin, direction)
            .iter()
            .find_map(|s| s.nearest(t_min, t_max))
    }

    fn frame(&self, p: DVec3, part: u32) -> Frame {
        let (leaf, own) = Csg::leaf_and_part(part);
        let f = self.leaves[leaf].frame(p, own);
        if self.complemented[leaf] {
            Frame {
                u: f.u,
                v: -f.v,
                w: -f.w,
            }
        } else {
            f
        }
    }

    /// The surface coordinates of the leaf the point is on.
    fn coordinates(&self, p: DVec3, part: u32) -> DVec2 {
        let (leaf, own) = Csg::leaf_and_part(part);
        self.leaves[leaf].coordinates(p, own)
    }

    fn plane_coordinates(&self, p: DVec3, part: u32) -> Option<DVec2> {
        let (leaf, own) = Csg::leaf_and_part(part);
        self.leaves[leaf].plane_coordinates(p, own)
    }

    /// The axes of the leaf the point is on (complementing a leaf turns its frame over, not
    /// its coordinates).
    fn coordinate_axes(&self, p: DVec3, part: u32) -> Option<[DVec3; 2]> {
        let (leaf, own) = Csg::leaf_and_part(part);
        self.leaves[leaf].coordinate_axes(p, own)
    }

    fn is_charted(&self) -> bool {
        self.leaves.iter().all(Shape::is_charted)
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        self.bounds
    }
}

/// `type = "union"`: inside any member.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnionKeys {
    of: Vec<ShapeKeys>,
}

impl UnionKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        csg(CsgOperation::Union, self.of)
    }
}

/// `type = "intersection"`: inside every member.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntersectionKeys {
    of: Vec<ShapeKeys>,
}

impl IntersectionKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        csg(CsgOperation::Intersection, self.of)
    }
}

/// `type = "difference"`: inside the first member and outside the others.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DifferenceKeys {
    of: Vec<ShapeKeys>,
}

impl DifferenceKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        csg(CsgOperation::Difference, self.of)
    }
}

/// `type = "inverse"`: outside the member.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InverseKeys {
    of: Box<ShapeKeys>,
}

impl InverseKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        csg(CsgOperation::Inverse, vec![*self.of])
    }
}

/// `operation` on the members' shapes.
fn csg(operation: CsgOperation, of: Vec<ShapeKeys>) -> Result<Shape, GeometryError> {
    let members = of
        .into_iter()
        .map(ShapeKeys::build)
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Shape::Csg(Csg::new(operation, members)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(a: f64, b: f64) -> Span {
        Span {
            enter: (a, 1),
            exit: (b, 2),
        }
    }

    fn ends(spans: &[Span]) -> Vec<(f64, f64)> {
        spans.iter().map(|s| (s.enter.0, s.exit.0)).collect()
    }

    #[test]
    fn span_lists_combine_like_sets_of_intervals() {
        let a = [span(0.0, 2.0), span(5.0, 7.0)];
        let b = [span(1.0, 3.0), span(7.0, 8.0), span(10.0, 11.0)];
        // Touching spans (7) merge in a union and share nothing in an intersection.
        assert_eq!(
            ends(&union(a.iter().chain(&b).copied().collect())),
            [(0.0, 3.0), (5.0, 8.0), (10.0, 11.0)]
        );
        assert_eq!(ends(&intersection(&a, &b)), [(1.0, 2.0)]);
        let inf = f64::INFINITY;
        assert_eq!(ends(&complement(&a)), [(-inf, 0.0), (2.0, 5.0), (7.0, inf)]);
        assert_eq!(ends(&complement(&[])), [(-inf, inf)]);
        assert!(complement(&[span(-inf, inf)]).is_empty());
    }

    #[test]
    fn complements_keep_the_parts_of_the_surfaces_they_start_and_end_on() {
        let c = complement(&[span(0.0, 2.0)]);
        assert_eq!(c[0].exit, (0.0, 1));
        assert_eq!(c[1].enter, (2.0, 2));
        assert_eq!(c[0].enter.1, Span::NO_PART);
    }
}
