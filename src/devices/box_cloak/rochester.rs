//! The extended Rochester cloak (Dr TIM's `EditableRochesterCloak` and the box cloak of
//! `BoxCloakType.ROCHESTER`, its `RochesterCloakMaker`): the four-lens Rochester cloak (Choi
//! and Howell, Opt. Express 22, 29465 (2014)) along the front–back axis, made to work for rays
//! off that axis by a shell of glenses round it.
//!
//! With h half the side length L, p and e the inner volume's transverse size in physical and
//! electromagnetic space (as fractions of L) and M = e/p its transverse magnification, the
//! outer lenses (focal length f₁ = L (M + 1)/(2 (M − 1))) fill the cube's front and back faces
//! and the inner lenses (f₂ = −L (M + 1)/(2 M (M − 1))) stand a distance d = h − f₁ − f₂ from
//! the centre; the inner volume is the cuboid of half-size p h across and d along the axis.
//! Round it, the outer surface runs from each edge of the front and back faces to a "belly", the
//! square of half-size 1.5 h across the middle, and the glenses of Dr TIM's construction (its
//! conjugate pairs, [`Glens::from_conjugate_pairs`]) fill the outer surface, the cuboid's sides
//! and the diagonal faces between them.
//!
//! Two things Dr TIM's maker does are not copied: it puts the outer lenses' principal points a
//! *unit* distance from the centre (on the faces only when L = 2; here always on the faces, where
//! its focal lengths assume them), and it gives the centre diagonal glenses a transmission
//! coefficient of 0.5 (a left-over diagnostic switch; here the cloak's own).

use glam::DVec3;

use super::{Axis, BoxCloakParameters};
use crate::devices::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::Transform;
use crate::surfaces::{Focus, Glens, Surface};

/// The extended Rochester cloak.
#[derive(Debug, Clone, PartialEq)]
pub struct RochesterCloak(pub BoxCloakParameters);

/// The cloak worked out in its own coordinates, its centre at the origin and its half side h
/// the unit of length (`place` maps them into the scene's): the inner volume's half-length d
/// along the axis and half-size p across, and the focal lengths.
struct Maker<'a> {
    b: &'a BoxCloakParameters,
    place: Transform,
    d: f64,
    across: f64,
    f1: f64,
    f2: f64,
}

impl RochesterCloak {
    fn maker(&self) -> Result<Maker<'_>, String> {
        let b = &self.0;
        b.check_precision()?;
        let (e, p) = (b.inner_volume_size_factor_em, b.inner_volume_size_factor_p);
        let m = e / p;
        // The inner lenses stand d = −L/(2M) from the centre: between it and the outer lenses
        // only where M < −1 (Dr TIM: "innerVolumeSizeFactorEM < -innerVolumeSizeFactorP").
        if m >= -1.0 {
            return Err(format!(
                "inner_volume_size_factor_em = {e} must be less than -inner_volume_size_factor_p \
                 = {}: the inner volume must be seen magnified and flipped, or the inner lenses \
                 would not lie between the centre and the outer lenses",
                -p
            ));
        }
        // Near M = −1 the outer lenses' focal length f₁ vanishes and the glenses' conjugate
        // pairs crowd together: refused before they lose their accuracy (measured: at
        // M = −1.01 and −1000 rays through the cloak stay on their lines to 1e-9).
        if m > -1.01 {
            return Err(format!(
                "inner_volume_size_factor_em / inner_volume_size_factor_p = {m} is too close to \
                 -1 (at least 0.01 below it): the outer lenses' focal length would vanish"
            ));
        }
        // Beyond M = −1000 the inner lenses' focal length f₂ ≈ −L/(2M) is too short for the
        // cloak to stay exact to 1e-9.
        if m < -1000.0 {
            return Err(format!(
                "inner_volume_size_factor_em / inner_volume_size_factor_p = {m} is below -1000: \
                 the inner lenses would be too close to the centre to trace exactly"
            ));
        }
        // In units of h = L/2.
        let (f1, f2) = ((m + 1.0) / (m - 1.0), -(m + 1.0) / (m * (m - 1.0)));
        let place = b.place();
        Ok(Maker {
            b,
            place,
            d: 1.0 - f1 - f2,
            across: p,
            f1,
            f2,
        })
    }
}

impl Maker<'_> {
    /// A glens face, placed in the scene.
    fn face(&self, name: String, vertices: Vec<DVec3>, glens: Glens) -> Result<Part, String> {
        let glens = glens
            .transformed(&self.place)
            .map_err(|e| format!("{name}: {e}"))?;
        let vertices = vertices.iter().map(|&v| self.place.point(v)).collect();
        self.b.face(name, vertices, Surface::Glens(glens))
    }

    /// A frame's edge from `a` to `b`, placed in the scene.
    fn edge(&self, e: &Edges, name: String, a: DVec3, b: DVec3) -> Result<Part, String> {
        e.part(name, self.place.point(a), self.place.point(b))
    }

    /// A frame's vertex at `at`, placed in the scene.
    fn vertex(&self, e: &Edges, name: String, at: DVec3) -> Result<Part, String> {
        e.vertex(name, self.place.point(at))
    }

    /// The outer cube's corner in the directions l, t, o.
    fn outer(&self, l: Axis, t: Axis, o: Axis) -> DVec3 {
        l.v + t.v + o.v
    }

    /// The belly's corner in the transverse directions t, o.
    fn halfway(&self, t: Axis, o: Axis) -> DVec3 {
        1.5 * (t.v + o.v)
    }

    /// The inner cuboid's corner in the directions l, t, o.
    fn inner(&self, l: Axis, t: Axis, o: Axis) -> DVec3 {
        self.d * l.v + self.across * (t.v + o.v)
    }

    /// The ideal lens of focal length f along `axis` (outside in positive space) with its
    /// principal point `principal_point`.
    fn lens(&self, axis: DVec3, principal_point: DVec3, f: f64) -> Glens {
        Glens {
            optical_axis: axis,
            focus: Focus::Finite {
                principal_point,
                focal_length_negative: -f,
                focal_length_positive: f,
            },
            transmission_coefficient: self.b.interface_transmission_coefficient,
        }
    }

    /// The glens on the polygon `vertices`, its positive space on the side of `towards`, that
    /// images q.0 to q.1 and r.0 to r.1 (Dr TIM's `CloakMaker.getConvexPolygonalGlens`).
    fn glens(
        &self,
        name: &str,
        vertices: &[DVec3],
        towards: Axis,
        q: (DVec3, DVec3),
        r: (DVec3, DVec3),
    ) -> Result<Glens, String> {
        let mut normal = (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]);
        if normal.dot(towards.v) < 0.0 {
            normal = -normal;
        }
        Glens::from_conjugate_pairs(
            vertices[0],
            normal,
            q,
            r,
            self.b.interface_transmission_coefficient,
        )
        .map_err(|e| format!("{name}: {e}"))
    }

    /// The glens's image of `object` (from negative into positive space if `into_positive`),
    /// its plane through `point`.
    fn image(
        name: &str,
        glens: &Glens,
        point: DVec3,
        object: DVec3,
        into_positive: bool,
    ) -> Result<DVec3, String> {
        glens.image(object, point, into_positive).ok_or_else(|| {
            format!("{name}: the image of {object} is at infinity for these parameters")
        })
    }

    /// The outer and inner lens on the axis `l` (Dr TIM's `addOnAxisLensesForAxialDirection`),
    /// with their parts.
    fn lenses(&self, l: Axis, parts: &mut Vec<Part>) -> Result<(Glens, Glens), String> {
        let [_, o, t] = self.b.axes();
        let outer = self.lens(l.v, l.v, self.f1);
        let inner = self.lens(l.v, self.d * l.v, self.f2);
        let square = |corner: &dyn Fn(Axis, Axis) -> DVec3| {
            vec![corner(t, o), corner(t, -o), corner(-t, -o), corner(-t, o)]
        };
        let outer_square = square(&|t, o| self.outer(l, t, o));
        let inner_square = square(&|t, o| self.inner(l, t, o));
        for (which, lens, square) in [
            ("outer", &outer, outer_square),
            ("inner", &inner, inner_square),
        ] {
            parts.push(self.face(format!("{} {which} lens", l.name), square, lens.clone())?);
        }
        Ok((outer, inner))
    }

    /// The glenses round the axis `l` on the side `t` (Dr TIM's
    /// `addSurfacesForLongitudinalTransverseDirectionCombo`), `o` the other transverse
    /// direction; with `middle` also those of the inner cuboid's side and the middle.
    fn surfaces(
        &self,
        (l, t, o): (Axis, Axis, Axis),
        (outside_lens, inside_lens): (&Glens, &Glens),
        middle: bool,
        parts: &mut Vec<Part>,
    ) -> Result<(), String> {
        let outside_point = l.v;
        let inside_point = self.d * l.v;
        let through_lenses = |name: &str, x: DVec3| -> Result<DVec3, String> {
            let y = Maker::image(name, inside_lens, inside_point, x, true)?;
            Maker::image(name, outside_lens, outside_point, y, true)
        };
        let outside =
            |name: &str, x: DVec3| Maker::image(name, outside_lens, outside_point, x, true);
        let back_through_lenses = |name: &str, y: DVec3| -> Result<DVec3, String> {
            let x = Maker::image(name, outside_lens, outside_point, y, false)?;
            Maker::image(name, inside_lens, inside_point, x, false)
        };

        // The outer surface from the face's edge to the belly.
        let name = format!("{} {} glens", l.name, t.name);
        let (v1, v2) = (self.inner(l, t, o), self.inner(l, t, -o));
        let outer_face = [
            self.outer(l, t, o),
            self.halfway(t, o),
            self.halfway(t, -o),
            self.outer(l, t, -o),
        ];
        let surface = self.glens(
            &name,
            &outer_face,
            t,
            (v1, outside(&name, v1)?),
            (v2, outside(&name, v2)?),
        )?;
        parts.push(self.face(name.clone(), outer_face.to_vec(), surface.clone())?);
        let back_through_surface =
            |x: DVec3| Maker::image(&name, &surface, outer_face[0], x, false);

        let (v3, v4) = (self.inner(l, -t, o), self.inner(l, -t, -o));
        let v8 = self.outer(l, -t, o);
        let v3_seen = back_through_surface(outside(&name, v3)?)?;
        let v4_seen = back_through_surface(outside(&name, v4)?)?;
        let diagonal = [
            self.outer(l, t, o),
            self.inner(l, t, o),
            self.inner(l, t, -o),
            self.outer(l, t, -o),
        ];
        let name = format!("{} {} diagonal glens", l.name, t.name);
        let g = self.glens(&name, &diagonal, t, (v3, v3_seen), (v4, v4_seen))?;
        parts.push(self.face(name, diagonal.to_vec(), g)?);

        let side = [self.outer(l, t, o), self.inner(l, t, o), self.halfway(t, o)];
        let name = format!("{} {} {} diagonal glens", l.name, t.name, o.name);
        let g = self.glens(
            &name,
            &side,
            t,
            (v3, v3_seen),
            (v8, back_through_surface(v8)?),
        )?;
        parts.push(self.face(name, side.to_vec(), g)?);

        let (v5, v6) = (self.inner(-l, t, o), self.inner(-l, t, -o));
        let centre_diagonal = [
            self.halfway(t, o),
            self.inner(l, t, o),
            self.inner(l, t, -o),
            self.halfway(t, -o),
        ];
        let name = format!("{} {} centre diagonal glens", l.name, t.name);
        let centre = self.glens(
            &name,
            &centre_diagonal,
            t,
            (v5, back_through_surface(through_lenses(&name, v5)?)?),
            (v6, back_through_surface(through_lenses(&name, v6)?)?),
        )?;
        parts.push(self.face(name.clone(), centre_diagonal.to_vec(), centre.clone())?);
        if !middle {
            return Ok(());
        }

        // The inner cuboid's side, and the middle's diagonal faces.
        let (h1, h2) = (self.halfway(t, o), self.halfway(t, -o));
        let cuboid_side = [
            self.inner(l, t, o),
            self.inner(-l, t, o),
            self.inner(-l, t, -o),
            self.inner(l, t, -o),
        ];
        let inner_name = format!("{} inner glens", t.name);
        let g = self.glens(
            &inner_name,
            &cuboid_side,
            t,
            (back_through_lenses(&inner_name, h1)?, h1),
            (back_through_lenses(&inner_name, h2)?, h2),
        )?;
        parts.push(self.face(inner_name, cuboid_side.to_vec(), g)?);

        let v7 = self.inner(-l, -t, o);
        let twice = |x: DVec3| -> Result<DVec3, String> {
            let y = back_through_surface(x)?;
            Maker::image(&name, &centre, centre_diagonal[0], y, false)
        };
        let middle_side = [
            self.inner(l, t, o),
            self.inner(-l, t, o),
            self.halfway(t, o),
        ];
        let side_name = format!("{} {} centre diagonal glens", t.name, o.name);
        let g = self.glens(
            &side_name,
            &middle_side,
            t,
            (v3, twice(outside(&side_name, v3)?)?),
            (v7, twice(through_lenses(&side_name, v7)?)?),
        )?;
        parts.push(self.face(side_name, middle_side.to_vec(), g)?);
        Ok(())
    }

    /// Dr TIM's frames along the axis `l` (its `addFrameElementsForAxialDirection`), with the
    /// belly's and the outer and inner edges along the axis for the front.
    fn frames(&self, l: Axis, e: &Edges, parts: &mut Vec<Part>) -> Result<(), String> {
        let [_, right, top] = self.b.axes();
        let corners = [(top, right), (top, -right), (-top, -right), (-top, right)];
        let label = |(t, o): (Axis, Axis)| format!("{} {}", t.name, o.name);
        let ring = |corner: &dyn Fn((Axis, Axis)) -> DVec3,
                    which: &str,
                    parts: &mut Vec<Part>|
         -> Result<(), String> {
            for (i, &c) in corners.iter().enumerate() {
                let next = corners[(i + 1) % 4];
                parts.push(self.edge(
                    e,
                    format!("{} {which} edge {} to {}", l.name, label(c), label(next)),
                    corner(c),
                    corner(next),
                )?);
                parts.push(self.vertex(
                    e,
                    format!("{} {which} vertex {}", l.name, label(c)),
                    corner(c),
                )?);
            }
            Ok(())
        };
        ring(&|(t, o)| self.outer(l, t, o), "outer", parts)?;
        ring(&|(t, o)| self.inner(l, t, o), "inner", parts)?;
        for c @ (t, o) in corners {
            parts.push(self.edge(
                e,
                format!("{} diagonal edge {}", l.name, label(c)),
                self.outer(l, t, o),
                self.inner(l, t, o),
            )?);
            parts.push(self.edge(
                e,
                format!("{} middle diagonal edge {}", l.name, label(c)),
                self.halfway(t, o),
                self.inner(l, t, o),
            )?);
        }
        if l.name == "front" {
            for (i, &c @ (t, o)) in corners.iter().enumerate() {
                let next = corners[(i + 1) % 4];
                parts.push(self.vertex(
                    e,
                    format!("belly vertex {}", label(c)),
                    self.halfway(t, o),
                )?);
                parts.push(self.edge(
                    e,
                    format!("belly edge {} to {}", label(c), label(next)),
                    self.halfway(t, o),
                    self.halfway(next.0, next.1),
                )?);
                parts.push(self.edge(
                    e,
                    format!("outer edge along the axis {}", label(c)),
                    self.outer(l, t, o),
                    self.outer(-l, t, o),
                )?);
                parts.push(self.edge(
                    e,
                    format!("inner edge along the axis {}", label(c)),
                    self.inner(l, t, o),
                    self.inner(-l, t, o),
                )?);
            }
        }
        Ok(())
    }
}

impl LensDevice for RochesterCloak {
    /// The lenses `front outer lens`, `front inner lens` (and `back`); round the front axis on
    /// its top side the glenses `front top glens` (the outer surface), `front top diagonal
    /// glens`, `front top right diagonal glens`, `front top centre diagonal glens`, `top inner
    /// glens` and `top right centre diagonal glens`, and likewise for the other sides (the back
    /// without the inner and middle ones, Dr TIM's construction); with `edges` Dr TIM's frames
    /// (`front outer edge top right to top left`, `front inner vertex top right`, `front
    /// diagonal edge ...`, `front middle diagonal edge ...`, `belly vertex ...`, `belly edge
    /// ...`, `outer edge along the axis ...`, `inner edge along the axis ...`).
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let m = self.maker()?;
        let mut parts = Vec::new();
        let [front, right, top] = m.b.axes();
        let front_lenses = m.lenses(front, &mut parts)?;
        let back_lenses = m.lenses(-front, &mut parts)?;
        for (t, o) in [(top, right), (right, -top), (-top, -right), (-right, top)] {
            m.surfaces(
                (front, t, o),
                (&front_lenses.0, &front_lenses.1),
                true,
                &mut parts,
            )?;
        }
        for (t, o) in [(top, -right), (-right, -top), (-top, right), (right, top)] {
            m.surfaces(
                (-front, t, o),
                (&back_lenses.0, &back_lenses.1),
                false,
                &mut parts,
            )?;
        }
        if let Some(e) = edges {
            m.frames(front, e, &mut parts)?;
            m.frames(-front, e, &mut parts)?;
        }
        Ok(parts)
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        self.0.edge_defaults()
    }
}
