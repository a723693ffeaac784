//! Property tests for the 4-wide BVH: on random triangle soups and random rays,
//! closest-hit and any-hit queries agree with brute force, and the tree's invariants hold;
//! also for soups with zero-area triangles, rays lying in the planes of boxes (axis-aligned
//! triangles met edge-on) and NaN directions. The wide tree's precomputed leaf triangles
//! (four-lane test) are checked in every instruction set against the one-at-a-time test, bit
//! for bit, including `t_max` at, just below and just above the hit, and zero; and packets
//! of eight rays traced together give each ray the one-ray query's answers.

use std::sync::Arc;

use mcrender_core::accel::{Isa, WideBvh, PACKET};
use mcrender_core::math::{Bounds3, Ray, Vec3};
use mcrender_core::shape::{Shape, Triangle, TriangleMesh};
use proptest::prelude::*;

fn vec3(range: f32) -> impl Strategy<Value = Vec3> {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A soup of triangles, each a random centre plus small random offsets.
fn soup() -> impl Strategy<Value = Vec<[Vec3; 3]>> {
    prop::collection::vec((vec3(10.0), vec3(1.5), vec3(1.5), vec3(1.5)), 1..300)
        .prop_map(|v| v.into_iter().map(|(c, a, b, d)| [c + a, c + b, c + d]).collect())
}

fn shapes_of(tris: &[[Vec3; 3]]) -> Vec<Shape> {
    let mesh = Arc::new(TriangleMesh {
        positions: tris.iter().flatten().copied().collect(),
        indices: (0..3 * tris.len() as u32).collect(),
        ..Default::default()
    });
    (0..tris.len() as u32)
        .map(|index| Shape::Triangle(Triangle::new(mesh.clone(), index)))
        .collect()
}

/// The wide tree of `shapes` with its leaf triangles precomputed, once per instruction set
/// this CPU supports (every one in CI; an unsupported one is reported, not silently left out).
fn block_trees(shapes: &[Shape], bounds: &[Bounds3]) -> Vec<WideBvh> {
    let mut wide = WideBvh::build(bounds);
    wide.attach_triangles(|i| match &shapes[i as usize] {
        Shape::Triangle(t) => Some(t.positions()),
        _ => None,
    });
    assert!(wide.triangle_blocks() > 0, "no leaf blocks were made");
    assert_eq!(wide.check_invariants(bounds), Ok(()));
    Isa::ALL
        .into_iter()
        .filter_map(|isa| {
            let mut w = wide.clone();
            match w.set_isa(isa) {
                Ok(()) => Some(w),
                Err(e) => {
                    eprintln!("NOT TESTED: {e}");
                    None
                }
            }
        })
        .collect()
}

/// The four-lane leaf test agrees with the one-at-a-time one bit for bit (same primitive,
/// distance and barycentrics), and any-hit with brute force, for `t_max` as given, at the
/// hit, just below and above it, and 0.
fn check_blocks(trees: &[WideBvh], shapes: &[Shape], ray: &Ray, t_max: f32) -> Result<(), TestCaseError> {
    let test = |i: u32, r: &Ray, t: f32| {
        shapes[i as usize].intersect(r, t).map(|h| {
            (
                h.t,
                [
                    h.t.to_bits(),
                    h.data[0].to_bits(),
                    h.data[1].to_bits(),
                    h.data[2].to_bits(),
                ],
            )
        })
    };
    let first = trees[0].closest_hit(ray, t_max, test).map(|h| h.1[0]);
    let mut t_maxes = vec![t_max, 0.0];
    if let Some(t) = first.map(f32::from_bits) {
        t_maxes.extend([t, t.next_down(), t.next_up()]);
    }
    for w in trees {
        for &t_max in &t_maxes {
            let one_at_a_time = w.closest_hit(ray, t_max, test);
            let four = w.closest_hit_triangles(ray, t_max, test, |_, h| {
                [h.t.to_bits(), h.b[0].to_bits(), h.b[1].to_bits(), h.b[2].to_bits()]
            });
            prop_assert_eq!(
                one_at_a_time,
                four,
                "{:?}: closest hit, ray {:?}, t_max {}",
                w.isa(),
                ray,
                t_max
            );
            let brute = shapes.iter().any(|s| s.intersect(ray, t_max).is_some());
            let any = w.any_hit_triangles(ray, t_max, |i, r, t| shapes[i as usize].intersect(r, t).is_some());
            prop_assert_eq!(brute, any, "{:?}: any hit, ray {:?}, t_max {}", w.isa(), ray, t_max);
        }
    }
    Ok(())
}

/// Packets of eight of `rays` (with every eighth ray left out of the active mask, and a
/// last partial packet) give each ray the one-ray query's closest distance, bit for bit, a
/// primitive that is hit there, and the one-ray any-hit answer.
fn check_packets(trees: &[WideBvh], shapes: &[Shape], rays: &[(Ray, f32)]) -> Result<(), TestCaseError> {
    let test = |i: u32, r: &Ray, t: f32| shapes[i as usize].intersect(r, t).map(|h| (h.t, h.t));
    for w in trees {
        for (k, group) in rays.chunks(PACKET).enumerate() {
            let packet: [Ray; PACKET] = std::array::from_fn(|r| group.get(r).map_or(group[0].0, |g| g.0));
            let t_max: [f32; PACKET] = std::array::from_fn(|r| group.get(r).map_or(0.0, |g| g.1));
            let left_out = k % PACKET;
            let active = ((1u32 << group.len()) - 1) & !(1 << left_out);
            let closest =
                w.closest_hit_triangles_packet(&packet, t_max, active, |_, i, r, t| test(i, r, t), |_, _, h| h.t);
            let blocked = w.any_hit_triangles_packet(&packet, t_max, active, |_, i, r, t| {
                shapes[i as usize].intersect(r, t).is_some()
            });
            for r in 0..PACKET {
                let (ray, t) = (&packet[r], t_max[r]);
                if active >> r & 1 == 0 {
                    prop_assert!(
                        closest[r].is_none() && blocked >> r & 1 == 0,
                        "{:?}: inactive ray {} answered",
                        w.isa(),
                        r
                    );
                    continue;
                }
                let one = w.closest_hit_triangles(ray, t, test, |_, h| h.t);
                prop_assert_eq!(
                    one.map(|h| h.1.to_bits()),
                    closest[r].map(|h| h.1.to_bits()),
                    "{:?}: packet closest distance, ray {:?}, t_max {}",
                    w.isa(),
                    ray,
                    t
                );
                if let Some((prim, t_hit)) = closest[r] {
                    let again = shapes[prim as usize].intersect(ray, t).map(|h| h.t.to_bits());
                    prop_assert_eq!(
                        again,
                        Some(t_hit.to_bits()),
                        "{:?}: packet primitive {} is not hit there",
                        w.isa(),
                        prim
                    );
                }
                let any = w.any_hit_triangles(ray, t, |i, r, t| shapes[i as usize].intersect(r, t).is_some());
                prop_assert_eq!(
                    any,
                    blocked >> r & 1 != 0,
                    "{:?}: packet any hit, ray {:?}, t_max {}",
                    w.isa(),
                    ray,
                    t
                );
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        // A fixed seed keeps CI deterministic; set PROPTEST_RNG_SEED to explore others.
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x6d63_7265_6e64),
        ..ProptestConfig::default()
    })]

    #[test]
    fn bvh_matches_brute_force(
        tris in soup(),
        rays in prop::collection::vec((vec3(15.0), vec3(1.0), any::<prop::sample::Index>(), any::<bool>()), 50),
    ) {
        let shapes = shapes_of(&tris);
        let bounds: Vec<Bounds3> = shapes.iter().map(Shape::bounds).collect();
        let wide = WideBvh::build(&bounds);
        prop_assert_eq!(wide.check_invariants(&bounds), Ok(()));
        let trees = block_trees(&shapes, &bounds);
        let mut traced = Vec::new();
        for (o, d, target, aimed) in rays {
            // Half the rays aim at a triangle's centroid, so they certainly hit something.
            let tri = &tris[target.index(tris.len())];
            let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
            let d = if aimed { centroid - o } else { d };
            let Some(d) = d.try_normalize() else { continue };
            let ray = Ray::new(o, d);
            let brute = shapes.iter().enumerate()
                .filter_map(|(i, s)| s.intersect(&ray, f32::INFINITY).map(|h| (i, h.t)))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let fast_wide = wide.closest_hit(&ray, f32::INFINITY, |i, r, t| shapes[i as usize].intersect(r, t).map(|h| (h.t, h.t)));
            prop_assert_eq!(brute.map(|b| b.1), fast_wide.map(|w| w.1), "wide closest distance differs");
            let area = (tri[1] - tri[0]).cross(tri[2] - tri[0]).length();
            let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
            // A ray grazing the triangle's plane may miss it within rounding error.
            if aimed && area > 1e-3 && n.dot(d).abs() > 1e-3 {
                prop_assert!(brute.is_some(), "a ray aimed at the centroid of {:?} missed everything: origin {o}, cos to plane {}", tri, n.dot(d));
            }
            match (brute, fast_wide) {
                (None, None) => {}
                (Some((_, tb)), Some((i, _))) => {
                    let tf = shapes[i as usize].intersect(&ray, f32::INFINITY).unwrap().t;
                    prop_assert_eq!(tb, tf, "closest distances differ");
                }
                (b, f) => prop_assert!(false, "brute {:?} vs bvh {:?}", b, f.map(|x| x.0)),
            }
            // Any-hit agrees with brute force for a segment ending before and after the hit.
            for t_max in [brute.map_or(5.0, |b| b.1 * 0.5), brute.map_or(50.0, |b| b.1 * 2.0)] {
                let any_brute = shapes.iter().any(|s| s.intersect(&ray, t_max).is_some());
                let any_wide = wide.any_hit(&ray, t_max, |i, r, t| shapes[i as usize].intersect(r, t).is_some());
                prop_assert_eq!(any_brute, any_wide);
            }
            check_blocks(&trees, &shapes, &ray, f32::INFINITY)?;
            let half = brute.map_or(5.0, |b| b.1 * 0.5);
            traced.extend([(ray, f32::INFINITY), (ray, half)]);
        }
        check_packets(&[trees, vec![wide]].concat(), &shapes, &traced)?;
    }
}

/// A soup of axis-aligned triangles (each flat in x, y or z, so its box is flat), some of
/// zero area.
fn flat_soup() -> impl Strategy<Value = Vec<[Vec3; 3]>> {
    prop::collection::vec((vec3(6.0), vec3(1.5), vec3(1.5), 0..3usize, 0..8u8), 1..200).prop_map(|v| {
        v.into_iter()
            .map(|(c, a, b, axis, kind)| {
                let mut t = [c, c + a, c + b];
                for p in &mut t {
                    p[axis] = c[axis].round();
                }
                if kind == 0 {
                    t[2] = t[1]; // zero area: two equal corners
                } else if kind == 1 {
                    t[2] = t[0] + 2.0 * (t[1] - t[0]); // zero area: collinear
                } else if kind < 5 {
                    t[2][axis] += 1.0; // standing on the plane, its bottom edge in it
                }
                t
            })
            .collect()
    })
}

/// Brute-force closest distance and any-hit answer.
fn brute(shapes: &[Shape], ray: &Ray, t_max: f32) -> (Option<f32>, bool) {
    let t = shapes
        .iter()
        .filter_map(|s| s.intersect(ray, t_max).map(|h| h.t))
        .min_by(f32::total_cmp);
    (t, t.is_some())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x7769_6465),
        ..ProptestConfig::default()
    })]

    /// Rays whose origin lies on the integer planes the flat triangles sit in, travelling
    /// inside such a plane (one direction component zero), plus NaN directions: the tree
    /// agree with brute force (NaN directions hit nothing).
    #[test]
    fn wide_bvh_handles_flat_boxes_degenerate_triangles_and_nan(
        tris in flat_soup(),
        rays in prop::collection::vec(
            (vec3(8.0), vec3(1.0), 0..3usize, 0..7u8, 0.1f32..20.0, any::<prop::sample::Index>()), 80),
    ) {
        let shapes = shapes_of(&tris);
        let bounds: Vec<Bounds3> = shapes.iter().map(Shape::bounds).collect();
        let wide = WideBvh::build(&bounds);
        prop_assert_eq!(wide.check_invariants(&bounds), Ok(()));
        let trees = block_trees(&shapes, &bounds);
        let mut traced = Vec::new();
        for (mut o, mut d, axis, kind, t_max, target) in rays {
            match kind {
                5 | 6 => {
                    // In the plane of a triangle's bottom edge, aimed at the edge's midpoint
                    // (the edge lies in the triangle's flat bounding-box face).
                    let tri = tris[target.index(tris.len())];
                    let Some(k) = (0..3).find(|&k| tri[0][k] == tri[1][k] && tri[2][k] != tri[0][k]) else {
                        continue;
                    };
                    o[k] = tri[0][k];
                    d = 0.5 * (tri[0] + tri[1]) - o;
                    d[k] = 0.0;
                }
                0..=2 => {
                    // In a plane: origin on an integer coordinate, no motion along that axis.
                    o[axis] = o[axis].round();
                    d[axis] = 0.0;
                }
                3 => d[axis] = f32::NAN,
                _ => {}
            }
            if d.x == 0.0 && d.y == 0.0 && d.z == 0.0 {
                continue;
            }
            let ray = Ray::new(o, d);
            let t_max = if kind == 4 { t_max } else { f32::INFINITY };
            let (t_brute, any_brute) = brute(&shapes, &ray, t_max);
            if kind == 3 {
                prop_assert!(t_brute.is_none(), "a NaN direction hit a triangle at {:?}", t_brute);
            }
            let t_wide = wide
                .closest_hit(&ray, t_max, |i, r, t| shapes[i as usize].intersect(r, t).map(|h| (h.t, h.t)))
                .map(|w| w.1);
            prop_assert_eq!(t_brute, t_wide, "wide closest hit, ray {:?}", ray);
            let any_wide = wide.any_hit(&ray, t_max, |i, r, t| shapes[i as usize].intersect(r, t).is_some());
            prop_assert_eq!(any_brute, any_wide, "wide any hit, ray {:?}", ray);
            check_blocks(&trees, &shapes, &ray, t_max)?;
            traced.push((ray, t_max));
        }
        check_packets(&[trees, vec![wide]].concat(), &shapes, &traced)?;
    }
}

/// A triangle fan sharing edges: rays aimed exactly at shared edges and vertices must hit
/// (the intersection is watertight).
#[test]
fn shared_edges_leave_no_gaps() {
    let n = 64;
    let mut positions = vec![Vec3::ZERO];
    for i in 0..=n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        positions.push(Vec3::new(a.cos(), a.sin(), 0.0));
    }
    let indices = (0..n).flat_map(|i| [0, i + 1, i + 2]).collect();
    let mesh = Arc::new(TriangleMesh {
        positions: positions.clone(),
        indices,
        ..Default::default()
    });
    let shapes: Vec<Shape> = (0..n)
        .map(|index| Shape::Triangle(Triangle::new(mesh.clone(), index)))
        .collect();
    for p in positions.iter().skip(1).take(n as usize) {
        let target = *p * 0.5; // on the shared edge from the centre
        for o in [Vec3::new(0.3, -0.2, 2.0), Vec3::new(-1.0, 0.7, -3.0)] {
            let ray = Ray::new(o, (target - o).normalize());
            assert!(
                shapes.iter().any(|s| s.intersect(&ray, f32::INFINITY).is_some()),
                "ray through {target} slipped through"
            );
        }
    }
}

/// A degenerate input whose tree is deep (boxes at exponentially growing distances: each
/// SAH split cuts off the nearest few), so queries may need a traversal stack of more than
/// a hundred entries; they must still agree with brute force.
#[test]
fn deep_trees_traverse_with_a_deep_stack() {
    let tris: Vec<[Vec3; 3]> = (0..340)
        .map(|i| {
            let x = 1.29f32.powi(i);
            let s = 0.3 * x.min(1e3);
            [Vec3::new(x, -s, -s), Vec3::new(x, s, -s), Vec3::new(x, 0.0, s)]
        })
        .collect();
    let shapes = shapes_of(&tris);
    let bounds: Vec<Bounds3> = shapes.iter().map(Shape::bounds).collect();
    let wide = WideBvh::build(&bounds);
    assert_eq!(wide.check_invariants(&bounds), Ok(()));
    assert!(
        wide.traversal_stack_size() > 128,
        "the tree is not deep enough to test a deep stack: {}",
        wide.traversal_stack_size()
    );
    let mut traced = Vec::new();
    for (i, tri) in tris.iter().enumerate().step_by(7) {
        let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
        for o in [Vec3::new(-1.0, 0.1, 0.05), centroid + Vec3::new(0.0, 0.2, -3.0)] {
            let ray = Ray::new(o, (centroid - o).normalize());
            let brute = shapes
                .iter()
                .filter_map(|s| s.intersect(&ray, f32::INFINITY).map(|h| h.t))
                .min_by(f32::total_cmp);
            let fast = wide.closest_hit(&ray, f32::INFINITY, |p, r, t| {
                shapes[p as usize].intersect(r, t).map(|h| (h.t, h.t))
            });
            assert_eq!(brute, fast.map(|f| f.1), "triangle {i}, origin {o}");
            let blocked = wide.any_hit(&ray, f32::INFINITY, |p, r, t| {
                shapes[p as usize].intersect(r, t).is_some()
            });
            assert_eq!(blocked, brute.is_some(), "triangle {i}, origin {o}");
            traced.push((ray, f32::INFINITY));
        }
    }
    check_packets(&[block_trees(&shapes, &bounds), vec![wide]].concat(), &shapes, &traced).unwrap();
}

/// A tree large enough to prefetch and to use block costs (70,000 triangles of a wavy
/// sheet): packets of camera-like and scattered rays agree with the one-ray queries.
#[test]
fn packets_on_a_large_tree() {
    let n = 187;
    let height = |x: usize, y: usize| (x as f32 * 0.37).sin() * (y as f32 * 0.23).cos();
    let mut tris = Vec::new();
    for y in 0..n {
        for x in 0..n {
            let p = |x: usize, y: usize| Vec3::new(x as f32, y as f32, height(x, y));
            tris.push([p(x, y), p(x + 1, y), p(x, y + 1)]);
            tris.push([p(x + 1, y), p(x + 1, y + 1), p(x, y + 1)]);
        }
    }
    let shapes = shapes_of(&tris);
    let bounds: Vec<Bounds3> = shapes.iter().map(Shape::bounds).collect();
    let trees = block_trees(&shapes, &bounds);
    assert!(trees[0].memory_bytes() > 1 << 20, "the tree is too small to prefetch");
    let mut seed = 11u32;
    let mut rnd = || {
        seed = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        (seed >> 8) as f32 / (1u32 << 24) as f32
    };
    let mut rays = Vec::new();
    for k in 0..800 {
        let ray = if k % 2 == 0 {
            // From a camera above the sheet, scanline order.
            let target = Vec3::new((k % 40) as f32 * 4.6, (k / 40) as f32 * 9.0, 0.0);
            let o = Vec3::new(90.0, 90.0, 60.0);
            Ray::new(o, target - o)
        } else {
            let o = Vec3::new(rnd() * 187.0, rnd() * 187.0, rnd() * 4.0 - 2.0);
            Ray::new(o, Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5))
        };
        rays.push((ray, if k % 3 == 0 { 2.0 } else { f32::INFINITY }));
    }
    check_packets(&trees, &shapes, &rays).unwrap();
}

/// After `reorder_by_leaves` the leaves list the reordered primitives in storage order, and
/// every query finds the same primitive as before (now under its new index).
#[test]
fn reordering_by_leaves_keeps_every_answer() {
    let tris: Vec<[Vec3; 3]> = (0..500u32)
        .map(|i| {
            let f = |k: u32| ((i.wrapping_mul(2_654_435_761).wrapping_add(k * 40_503)) % 1000) as f32 / 50.0 - 10.0;
            let c = Vec3::new(f(1), f(2), f(3));
            [c, c + Vec3::new(0.0, 2.5, 0.3), c + Vec3::new(0.3, 0.0, 2.5)]
        })
        .collect();
    let shapes = shapes_of(&tris);
    let bounds: Vec<Bounds3> = shapes.iter().map(Shape::bounds).collect();
    let original = WideBvh::build(&bounds);
    let mut reordered = original.clone();
    let ids: Vec<usize> = (0..shapes.len()).collect();
    let ids = reordered.reorder_by_leaves(ids);
    assert_eq!(reordered.prim_indices(), (0..shapes.len() as u32).collect::<Vec<_>>());
    let moved: Vec<&Shape> = ids.iter().map(|&i| &shapes[i]).collect();
    let moved_bounds: Vec<Bounds3> = moved.iter().map(|s| s.bounds()).collect();
    assert_eq!(reordered.check_invariants(&moved_bounds), Ok(()));
    let mut hits = 0;
    for k in 0..200u32 {
        let o = Vec3::new(-15.0, (k % 20) as f32 - 10.0, (k / 20) as f32 * 2.0 - 10.0);
        let ray = Ray::new(o, Vec3::new(1.0, 0.05, -0.03).normalize());
        let before = original.closest_hit(&ray, f32::INFINITY, |p, r, t| {
            shapes[p as usize].intersect(r, t).map(|h| (h.t, ()))
        });
        let after = reordered.closest_hit(&ray, f32::INFINITY, |p, r, t| {
            moved[p as usize].intersect(r, t).map(|h| (h.t, ()))
        });
        assert_eq!(
            before.map(|b| b.0 as usize),
            after.map(|a| ids[a.0 as usize]),
            "ray {k}"
        );
        hits += usize::from(before.is_some());
    }
    assert!(hits >= 20, "only {hits} of 200 rays hit: the test shows little");
}

/// Coincident and overlapping copies of the same triangles: where two lanes hit at the same
/// distance, the four-lane test keeps the one the one-at-a-time test keeps.
#[test]
fn coincident_triangles_resolve_ties_alike() {
    let base: Vec<[Vec3; 3]> = (0..60)
        .map(|i| {
            let c = Vec3::new((i % 6) as f32, (i / 6) as f32 * 0.5, 0.0);
            [c, c + Vec3::new(1.2, 0.0, 0.0), c + Vec3::new(0.0, 1.2, 0.0)]
        })
        .collect();
    let tris: Vec<[Vec3; 3]> = base.iter().flat_map(|t| [*t, *t, [t[1], t[2], t[0]]]).collect();
    let shapes = shapes_of(&tris);
    let bounds: Vec<Bounds3> = shapes.iter().map(Shape::bounds).collect();
    let trees = block_trees(&shapes, &bounds);
    let mut hits = 0;
    for k in 0..400u32 {
        let o = Vec3::new((k % 20) as f32 * 0.3 - 0.5, (k / 20) as f32 * 0.3 - 0.5, 2.0);
        let ray = Ray::new(o, Vec3::new(0.1, 0.05, -1.0));
        check_blocks(&trees, &shapes, &ray, f32::INFINITY).unwrap();
        hits += usize::from(trees[0].any_hit_triangles(&ray, f32::INFINITY, |_, _, _| false));
    }
    assert!(hits > 100, "only {hits} of 400 rays hit: the test shows little");
}
