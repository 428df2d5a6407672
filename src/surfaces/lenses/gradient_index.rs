//! Gradient-index lenses traced through their actual refractive-index profile n(r), by
//! numerically integrating the ray equation d/ds (n dr/ds) = ∇n.
//!
//! With the parameter τ, dτ = ds/n, and the optical direction vector p = n dr/ds, the ray
//! equation is the Hamiltonian system dr/dτ = p, dp/dτ = n∇n = ∇(n²)/2, on which |p| = n; the
//! optical path length ∫n ds = ∫n² dτ is integrated alongside. Lengths are in units of the
//! lens radius. The system is integrated by adaptive Dormand–Prince steps from the entry point
//! until the ray crosses the surface again, located to rounding.
//!
//! This is the check on §3's closed forms: integrated rays leave where Eqs 5–10 say.

use glam::DVec3;

use super::IndexProfile;
use crate::geometry::Exit;
use crate::geometry::Sphere;
use crate::math::DormandPrince;

/// Local error tolerance of each integration step. Exit points agree with the closed forms to
/// about 1e-11 R for the Luneburg and Maxwell-fisheye profiles (for rays not within a few
/// degrees of grazing incidence, see [`GRAZING`]); for Eaton's, whose rays swing
/// round the singular centre, the orientation of the orbit is off by about 1e-12 R/b for
/// impact parameter b (a tolerance of 1e-10 would be twice as fast but 1e-10 R/b off).
const SOLVER: DormandPrince = DormandPrince {
    relative: 1e-12,
    absolute: 1e-12,
    max_steps: 100_000,
};

/// Impact parameter (in units of R) below which a ray counts as aimed at the centre of a
/// profile that is singular there. Integration errors grow as 1e-12/b (1e-7 R at this b), so
/// such a ray is given the b → 0 limit of its neighbours' orbits instead: turned back through
/// π, leaving from its entry point mirrored in the line through the centre along the ray (the
/// trajectory is symmetric about its closest approach).
const RADIAL: f64 = 1e-5;

/// Straight-line chord (in units of R) below which the exit of a grazing ray cannot be
/// located: along such a path |r|² − 1 stays within rounding of 0. These rays (entering within
/// about 5e-8 rad of the tangent, some 1e-15 of a lens's area) are passed straight across the
/// chord. That is not the grazing limit of every profile: where the index falls outwards as
/// fast as in the built-in three (n′ = −n/R at the surface), grazing rays follow the surface.
/// Away from this, the exit error grows as the entry nears grazing, as about 1e-12 R / cos θ.
const GRAZING: f64 = 1e-7;

/// A lens whose rays follow the ray equation through `profile`.
#[derive(Debug, Clone, PartialEq)]
pub struct GradientIndex {
    pub profile: IndexProfile,
}

impl GradientIndex {
    /// The ray leaving the lens after entering (already refracted into the lens material) at
    /// `p` with direction `d`. The path length is ∫n ds in the profile's own n. `None` if the
    /// ray does not leave within the integrator's step limit (a trapped ray).
    pub fn transmit(&self, lens: &Sphere, p: DVec3, d: DVec3) -> Option<Exit> {
        self.transmit_observed(lens, p, d, &mut |_| {})
    }

    /// [`Self::transmit`], showing `inside` the points of the curved path between entry and
    /// exit, in order: the integrator's accepted steps; the centre for a ray aimed at a
    /// singular centre; none for a grazing ray, which crosses straight.
    pub fn transmit_observed(
        &self,
        lens: &Sphere,
        p: DVec3,
        d: DVec3,
        inside: &mut dyn FnMut(DVec3),
    ) -> Option<Exit> {
        let (centre, radius) = (lens.centre(), lens.radius());
        let d = d.normalize();
        let x0 = ((p - centre) / radius).normalize();
        let chord = -2.0 * x0.dot(d);
        if chord < GRAZING {
            return Some(Exit::chord(p, p + chord.max(0.0) * radius * d, d));
        }
        if let Some(return_path) = self.profile.singular_return_path()
            && x0.cross(d).length() < RADIAL
        {
            let across = x0 - x0.dot(d) * d;
            // The limiting orbit runs into the centre and back out.
            inside(centre);
            return Some(Exit {
                point: p - 2.0 * radius * across,
                direction: -d,
                path: radius * return_path,
            });
        }
        let n0 = self.profile.n(1.0);
        let start = [x0.x, x0.y, x0.z, n0 * d.x, n0 * d.y, n0 * d.z, 0.0];
        let f = |y: &[f64; 7]| {
            let x = DVec3::new(y[0], y[1], y[2]);
            let p = DVec3::new(y[3], y[4], y[5]);
            let force = self.profile.force(x);
            [p.x, p.y, p.z, force.x, force.y, force.z, p.length_squared()]
        };
        // g = |x|² − 1 crosses zero upwards where the ray leaves; dg/dτ = 2 x·p.
        let event = |y: &[f64; 7], dy: &[f64; 7]| {
            let g = y[0] * y[0] + y[1] * y[1] + y[2] * y[2] - 1.0;
            (g, 2.0 * (y[0] * dy[0] + y[1] * dy[1] + y[2] * dy[2]))
        };
        // The first step covers a quarter of the straight chord (|dr/dτ| = n), so the ray is
        // well inside before the event is looked for.
        let step = |y: &[f64; 7]| inside(centre + radius * DVec3::new(y[0], y[1], y[2]));
        let y = SOLVER.integrate_observed(f, start, 0.25 * chord / (n0 * n0), event, step)?;
        let x = DVec3::new(y[0], y[1], y[2]).normalize();
        let direction = DVec3::new(y[3], y[4], y[5]).normalize();
        Some(Exit {
            point: centre + radius * x,
            direction,
            path: radius * y[6],
        })
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI};

    use super::*;
    use crate::surfaces::lenses::{eaton, luneburg, maxwell_fisheye};

    /// Rays entering a lens of radius 2 at (1, −1, 3) with impact parameters spread across
    /// (0, R) and planes of incidence turning about the lens: (entry point, unit direction).
    fn incident_rays(count: usize) -> (Sphere, Vec<(DVec3, DVec3)>) {
        let lens = Sphere::new(DVec3::new(1.0, -1.0, 3.0), 2.0).unwrap();
        let rays = (0..count)
            .map(|k| {
                let b = (k as f64 + 0.5) / count as f64;
                let turn = k as f64 * 2.399_963; // golden angle
                let tilt = (k as f64 * 0.618_034).fract() * 3.0 - 1.5;
                let d = DVec3::new(tilt.cos() * turn.cos(), tilt.sin(), tilt.cos() * turn.sin());
                let e = d.any_orthonormal_vector();
                let e = e * turn.cos() + d.cross(e) * turn.sin();
                let x = b * e - (1.0 - b * b).sqrt() * d;
                (lens.centre() + lens.radius() * x, d)
            })
            .collect();
        (lens, rays)
    }

    fn assert_matches(profile: IndexProfile, closed: fn(&Sphere, DVec3, DVec3) -> Exit) {
        let (lens, rays) = incident_rays(200);
        let law = GradientIndex { profile };
        let (mut worst_point, mut worst_angle) = (0.0f64, 0.0f64);
        for (p, d) in rays {
            let integrated = law.transmit(&lens, p, d).unwrap();
            let expected = closed(&lens, p, d);
            worst_point =
                worst_point.max(integrated.point.distance(expected.point) / lens.radius());
            // The chord between unit vectors is the angle between them, to third order (acos
            // loses half the digits near 0).
            worst_angle = worst_angle.max(integrated.direction.distance(expected.direction));
        }
        assert!(
            worst_point < 1e-6 && worst_angle < 1e-6,
            "{}: exit points within {worst_point:e} R, directions within {worst_angle:e} rad",
            law.profile.name()
        );
    }

    #[test]
    fn integrated_luneburg_profile_leaves_where_eqs_5_and_6_say() {
        assert_matches(IndexProfile::Luneburg, luneburg);
    }

    #[test]
    fn integrated_eaton_profile_leaves_where_eqs_7_and_8_say() {
        assert_matches(IndexProfile::Eaton, eaton);
    }

    #[test]
    fn integrated_maxwell_fisheye_profile_leaves_where_eqs_9_and_10_say() {
        assert_matches(IndexProfile::MaxwellFisheye, maxwell_fisheye);
    }

    /// A ray along +z entering the unit lens at the origin with impact parameter `b`, and its
    /// integrated exit.
    fn along_z(profile: IndexProfile, b: f64) -> (DVec3, Exit) {
        let lens = Sphere::new(DVec3::ZERO, 1.0).unwrap();
        let p = DVec3::new(b, 0.0, -(1.0 - b * b).sqrt());
        (
            p,
            GradientIndex { profile }
                .transmit(&lens, p, DVec3::Z)
                .unwrap(),
        )
    }

    /// Fermat: the rays of a perfect image have equal optical paths, so the integrated ∫n ds
    /// (the time a ray takes) must make them equal. Each expected value is the path of the ray
    /// through the centre, an integral done by hand.
    #[test]
    fn optical_paths_of_perfectly_imaged_rays_are_equal() {
        for k in 1..20 {
            let b = k as f64 / 20.0;
            // Luneburg: from the plane z = −1 to the focus (0, 0, 1):
            // 2∫₀¹ √(2 − ρ²) dρ = 1 + π/2.
            let (p, e) = along_z(IndexProfile::Luneburg, b);
            let total = (p.z + 1.0) + e.path;
            assert!(
                (total - (1.0 + FRAC_PI_2)).abs() < 1e-9,
                "Luneburg b = {b}: {total}"
            );
            // Maxwell fisheye: from P to its antipode, 2∫₀¹ 2/(1 + ρ²) dρ = π.
            let (_, e) = along_z(IndexProfile::MaxwellFisheye, b);
            assert!((e.path - PI).abs() < 1e-9, "Maxwell b = {b}: {}", e.path);
            // Eaton: from the plane z = −1 back to it, π + 2.
            let (p, e) = along_z(IndexProfile::Eaton, b);
            let total = (p.z + 1.0) + e.path + (e.point.z + 1.0);
            assert!((total - (PI + 2.0)).abs() < 1e-8, "Eaton b = {b}: {total}");
        }
    }

    #[test]
    fn a_ray_aimed_at_the_eaton_centre_is_turned_straight_back() {
        let (p, e) = along_z(IndexProfile::Eaton, 1e-7);
        assert_eq!(e.direction, -DVec3::Z);
        assert!((e.point - DVec3::new(-p.x, 0.0, p.z)).length() < 1e-15);
        assert_eq!(e.path, PI + 2.0, "the radial return trip");
    }

    #[test]
    fn a_table_sampled_from_a_profile_traces_like_the_profile() {
        let rho: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
        let n = rho.iter().map(|&r| IndexProfile::Luneburg.n(r)).collect();
        let table =
            IndexProfile::Table(crate::surfaces::lenses::TableProfile::new(rho, n).unwrap());
        for k in 1..10 {
            let b = k as f64 / 10.0;
            let (_, exact) = along_z(IndexProfile::Luneburg, b);
            let (_, tabled) = along_z(table.clone(), b);
            assert!(exact.point.distance(tabled.point) < 1e-5, "b = {b}");
        }
    }

    #[test]
    fn near_grazing_rays_leave_within_the_stated_conditioning() {
        // Exit error about 1e-12 R / cos θ (see GRAZING); asserted with a factor of 10 spare.
        for (profile, closed) in [
            (
                IndexProfile::Luneburg,
                luneburg as fn(&Sphere, DVec3, DVec3) -> Exit,
            ),
            (IndexProfile::Eaton, eaton),
            (IndexProfile::MaxwellFisheye, maxwell_fisheye),
        ] {
            for cos in [1e-2f64, 1e-3, 1e-4, 1e-5, 1e-6] {
                let lens = Sphere::new(DVec3::ZERO, 1.0).unwrap();
                let b = (1.0 - cos * cos).sqrt();
                let (p, e) = along_z(profile.clone(), b);
                let error = e.point.distance(closed(&lens, p, DVec3::Z).point);
                assert!(
                    error < 1e-11 / cos,
                    "{} cos θ {cos}: {error:e}",
                    profile.name()
                );
            }
        }
    }
}
