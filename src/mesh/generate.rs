//! Test meshes generated in code, so tests, examples and benchmarks need no downloads.

use std::f64::consts::PI;

use glam::DVec3;

use super::Mesh;

/// A bumpy unit sphere centred at the origin with at least `triangles` triangles (and at least
/// 8): a latitude–longitude grid of r rings and 2r segments (4r(r − 1) triangles, the smallest
/// such r), each vertex at distance 1 + `displacement` · sin 7x · sin 7y · sin 7z from the
/// centre along its unit direction (x, y, z). Vertex normals are the area-weighted face
/// normals. `displacement` 0 gives a faceted sphere inscribed in the unit sphere.
pub fn displaced_sphere(triangles: usize, displacement: f64) -> Mesh {
    let rings = rings(triangles);
    let segments = 2 * rings;
    let radius =
        |d: DVec3| 1.0 + displacement * (7.0 * d.x).sin() * (7.0 * d.y).sin() * (7.0 * d.z).sin();
    let point = |d: DVec3| d * radius(d);

    // Vertex 0 is the north pole (+y), then rings 1..rings-1 of `segments` vertices each, then
    // the south pole.
    let mut vertices = Vec::with_capacity(2 + (rings - 1) * segments);
    vertices.push(point(DVec3::Y));
    for ring in 1..rings {
        let theta = PI * ring as f64 / rings as f64;
        for s in 0..segments {
            let phi = 2.0 * PI * s as f64 / segments as f64;
            let d = DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            );
            vertices.push(point(d));
        }
    }
    vertices.push(point(DVec3::NEG_Y));
    let south = (vertices.len() - 1) as u32;

    let at = |ring: usize, s: usize| (1 + (ring - 1) * segments + s % segments) as u32;
    let mut tris = Vec::with_capacity(4 * rings * (rings - 1));
    for s in 0..segments {
        tris.push([0, at(1, s), at(1, s + 1)]);
    }
    for ring in 1..rings - 1 {
        for s in 0..segments {
            let (a, b) = (at(ring, s), at(ring, s + 1));
            let (c, d) = (at(ring + 1, s), at(ring + 1, s + 1));
            tris.push([a, c, d]);
            tris.push([a, d, b]);
        }
    }
    for s in 0..segments {
        tris.push([south, at(rings - 1, s + 1), at(rings - 1, s)]);
    }

    let mut mesh = Mesh {
        name: "displaced sphere".into(),
        vertices,
        triangles: tris,
        normals: None,
    };
    mesh.normals = Some(mesh.vertex_normals());
    mesh
}

/// The rings r of [`displaced_sphere`]'s grid for at least `triangles` triangles: the smallest
/// r ≥ 2 with 4r(r − 1) ≥ `triangles`.
fn rings(triangles: usize) -> usize {
    // Start just below the solution of 4r(r − 1) = triangles (4r² underestimates it).
    let mut rings = ((triangles as f64 / 4.0).sqrt() as usize).max(2);
    while 4 * rings * (rings - 1) < triangles {
        rings += 1;
    }
    rings
}

/// The triangles and vertices of [`displaced_sphere`]`(triangles, _)`, without making it.
pub fn displaced_sphere_size(triangles: usize) -> (u64, u64) {
    let r = rings(triangles) as u64;
    (4 * r * (r - 1), 2 + (r - 1) * 2 * r)
}

/// Bytes [`displaced_sphere`]`(triangles, _)` holds at its peak, generously: its vertices and
/// their normals, 24 bytes each, with a second copy of the normals while they are summed, and
/// its triangles, 12 bytes each (writing it adds only a small buffer).
pub fn displaced_sphere_memory(triangles: usize) -> u64 {
    let (triangles, vertices) = displaced_sphere_size(triangles);
    3 * 24 * vertices + 12 * triangles
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_count_is_the_smallest_grid_with_at_least_the_request() {
        for n in [0, 8, 9, 100, 12345] {
            let m = displaced_sphere(n, 0.1);
            let t = m.triangles.len();
            assert!(t >= n.max(8), "{n} -> {t}");
            let r = ((1.0 + (1.0 + t as f64).sqrt()) / 2.0).round() as usize;
            assert_eq!(4 * r * (r - 1), t);
            assert!(
                4 * (r - 1) * (r - 2) < n.max(8),
                "{n} -> {t}: not the smallest"
            );
        }
    }

    #[test]
    fn the_memory_estimate_covers_what_the_mesh_holds() {
        for n in [1, 100, 12345, 1_000_000] {
            let m = displaced_sphere(n, 0.1);
            let (triangles, vertices) = displaced_sphere_size(n);
            assert_eq!(
                (m.triangles.len() as u64, m.vertices.len() as u64),
                (triangles, vertices)
            );
            let normals = m.normals.as_ref().unwrap();
            let held =
                24 * (m.vertices.capacity() + normals.capacity()) + 12 * m.triangles.capacity();
            let estimate = displaced_sphere_memory(n);
            // Generous by the normals' second copy, and by no more.
            assert!(held as u64 <= estimate, "{n}: {held} > {estimate}");
            assert!(estimate <= held as u64 + 24 * vertices, "{n}: {estimate}");
        }
    }

    #[test]
    fn the_sphere_is_closed_and_wound_outwards() {
        let m = displaced_sphere(2000, 0.0);
        // Closed: every edge is shared by exactly two triangles, in opposite directions.
        let mut edges = std::collections::HashMap::new();
        for t in &m.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        assert!(
            edges
                .iter()
                .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
        );
        // Outward: the signed volume (divergence theorem) is positive and close to 4π/3.
        let volume: f64 = m
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.vertices[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        assert!((volume - 4.0 * PI / 3.0).abs() < 0.05, "{volume}");
        for (v, n) in m.vertices.iter().zip(m.normals.as_ref().unwrap()) {
            assert!((v.length() - 1.0).abs() < 1e-12);
            assert!(n.dot(*v) > 0.99, "normal {n} at {v}");
        }
    }
}
