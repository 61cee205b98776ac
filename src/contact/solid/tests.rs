//! Tests of the solids' signed distances, faces' shortcut and samples (`super`).

use super::*;

/// The signed distance against brute force: the distance to a dense cloud of surface
/// points, signed by an independent inside test, at random points about each solid.
#[test]
fn signed_distance_against_surface_points() {
    let l_shape = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(2.0, 1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(1.0, 2.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
    ];
    let plate = Solid::plate(&l_shape, 0.3, 0.1).unwrap();
    let cube = Solid::cuboid(Vec3::new(1.0, 0.5, 0.25), Vec3::new(0.1, 0.2, 0.3), 0.1).unwrap();
    let cyl = Solid::cylinder(0.5, 0.4, 0.1).unwrap();
    let mut seed = 12345_u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    // The plate is thin, its rim rounded; the same plate with a sharp rim too.
    let SolidKind::Prism { rim_radius: r, .. } = plate.kind else { panic!("a prism") };
    assert_eq!(r, 0.075);
    let mut sharp = plate.clone();
    if let SolidKind::Prism { rim_radius, .. } = &mut sharp.kind {
        *rim_radius = 0.0;
    }
    let box_of_plate = (Vec3::new(-0.5, -0.5, -0.5), Vec3::new(2.5, 2.5, 0.5));
    for (solid, (lo, hi)) in [
        (&plate, box_of_plate),
        (&sharp, box_of_plate),
        (&cube, (Vec3::new(-0.6, -0.3, 0.0), Vec3::new(0.8, 0.7, 0.6))),
        (&cyl, (Vec3::new(-0.7, -0.7, -0.4), Vec3::new(0.7, 0.7, 0.4))),
    ] {
        for _ in 0..400 {
            let p = Vec3::new(lo.x + (hi.x - lo.x) * rnd(), lo.y + (hi.y - lo.y) * rnd(), lo.z + (hi.z - lo.z) * rnd());
            let (d, n) = solid.signed_distance(&p);
            // Moving along the normal by a small step changes the distance by that step
            // (the gradient of a distance has unit length and points along it).
            let e = 1e-6;
            let (d2, _) = solid.signed_distance(&(p + n * e));
            assert!((d2 - d - e).abs() < 1e-9, "{:?}: gradient at {p:?}: {d} → {d2}", solid.kind);
            let foot = p - n * d;
            let (sharp_d, _) = sharp.signed_distance(&p);
            if std::ptr::eq(solid, &plate) && d > 0.0 && sharp_d != d {
                // Outside the rounded rim, where the outline's vertices make the rounding
                // of the extrusion a bound: at least the sharp plate's distance (the
                // rounded plate lies within it) and at most (√2 − 1) r more.
                assert!(sharp_d <= d && d <= sharp_d + 0.415 * r, "{p:?}: {d} against {sharp_d}");
            } else {
                // The foot of the normal is on the surface: distance zero there (inside
                // the rounded plate everywhere: the depth a contact reads is exact).
                assert!(solid.signed_distance(&foot).0.abs() < 1e-12, "{:?}: foot of {p:?}", solid.kind);
            }
        }
    }
}

/// A point 0.1 mm inside a thin plate under its top face, carried across the plate's edge
/// and out: its depth and normal change continuously (the normal turns from the face's to
/// the side's within the rim's rounding, by at most 2e-3 rad per micrometre travelled,
/// the rounding's 1/r = 1/(2.5 mm) = 4e-4 rad/µm with margin), and under the face away
/// from the edge the depth is the face's, 0.1 mm, exactly as without the rounding. The
/// same plate with a sharp rim turns its normal by 90° at once where the face and the side
/// are equally near (checked here, so that the test sees what it guards against).
#[test]
fn a_thin_plates_normal_turns_smoothly_over_its_rim() {
    let square =
        [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let plate = Solid::plate(&square, 0.01, 0.01).unwrap();
    let SolidKind::Prism { rim_radius, .. } = plate.kind else { panic!("a prism") };
    assert_eq!(rim_radius, 0.0025);
    let mut sharp = plate.clone();
    if let SolidKind::Prism { rim_radius, .. } = &mut sharp.kind {
        *rim_radius = 0.0;
    }
    // The solid frame's origin is the square's centre, its z the square's normal.
    let at = |x: f64| plate.origin_in_body + plate.dcm_s_b.transpose() * Vec3::new(x, 0.0, 0.005 - 1e-4);
    assert_eq!(plate.signed_distance(&at(0.0)).0, sharp.signed_distance(&at(0.0)).0);
    assert!((plate.signed_distance(&at(0.0)).0 + 1e-4).abs() < 1e-15);
    let turn = |solid: &Solid| {
        let (mut worst_turn, mut worst_jump) = (0.0_f64, 0.0_f64);
        let (mut d0, mut n0) = solid.signed_distance(&at(0.49));
        for k in 1..=15_000 {
            let (d, n) = solid.signed_distance(&at(0.49 + k as f64 * 1e-6));
            worst_turn = worst_turn.max(n0.angle(&n));
            worst_jump = worst_jump.max((d - d0).abs());
            (d0, n0) = (d, n);
        }
        (worst_turn, worst_jump)
    };
    let (rounded, step) = turn(&plate);
    assert!(rounded < 2e-3, "the normal turned by {rounded} rad in 1 µm");
    // The distance is 1-Lipschitz: 1 µm of travel changes it by at most 1 µm.
    assert!(step <= 1e-6 * (1.0 + 1e-9), "{step}");
    let (sharp_turn, _) = turn(&sharp);
    assert!(sharp_turn > 1.5, "the sharp rim's normal turned by {sharp_turn} rad at most");
}

/// The face shortcut gives the full signed distance to the last bit wherever it answers,
/// and answers for points well inside a prism's or a cylinder's outline near a face.
#[test]
fn face_distance_is_the_signed_distance_where_it_answers() {
    let square =
        [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let plate = Solid::plate(&square, 0.02, 0.01).unwrap();
    let cyl = Solid::cylinder(0.5, 0.4, 0.1).unwrap();
    let mut seed = 777_u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for solid in [&plate, &cyl] {
        let mut answered = 0;
        for _ in 0..2000 {
            let p = Vec3::new(2.0 * rnd() - 0.5, 2.0 * rnd() - 0.5, 0.6 * rnd() - 0.3);
            let (d, lateral) = solid.distance_and_lateral(&p);
            assert_eq!(d, solid.signed_distance(&p).0);
            for slack in [0.0, 1e-3] {
                if let Some(face) = solid.face_distance(&p, lateral + slack) {
                    assert_eq!(face, solid.signed_distance(&p), "{:?} at {p:?}", solid.kind);
                    answered += 1;
                }
            }
        }
        assert!(answered > 500, "{:?}: {answered}", solid.kind);
    }
}

/// A convex outline's short way ([`outline_distance`]) gives the full computation's
/// distance and gradient (to rounding; the gradient to 1e-9, as the nearest edge is
/// found by different arithmetic) inside, across an edge and past a corner, with the
/// same derivative in dual numbers (the exact Jacobian's path); and only convex outlines
/// are taken for convex.
#[test]
fn convex_outlines_take_the_nearest_line() {
    use num_dual::Dual64;
    let hexagon: Vec<[f64; 2]> =
        (0..6).map(|k| (k as f64 * std::f64::consts::FRAC_PI_3).sin_cos()).map(|(s, c)| [c, s]).collect();
    let triangle = [[0.0, 0.0], [1.0, 0.0], [0.2, 0.7]];
    let cut = [[0.1, 0.0], [0.9, 0.0], [1.0, 0.1], [1.0, 0.6], [0.9, 0.7], [0.1, 0.7], [0.0, 0.6], [0.0, 0.1]];
    let l_shape = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
    let straight = [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [0.0, 1.0]];
    assert!(is_convex(&hexagon) && is_convex(&triangle) && is_convex(&cut));
    // Two edges in line are left to the full computation.
    assert!(!is_convex(&l_shape) && !is_convex(&straight));
    let mut seed = 4242_u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for polygon in [&hexagon[..], &triangle, &cut] {
        let edges = Edge::of(polygon);
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..5000 {
            let p = [2.0 * rnd() - 0.5, 2.0 * rnd() - 0.5];
            let (d, g) = outline_distance(&edges, true, p);
            let (d0, g0) = polygon_distance(&edges, p);
            let close = (d - d0).abs() < 1e-12 && (g[0] - g0[0]).abs() < 1e-9 && (g[1] - g0[1]).abs() < 1e-9;
            assert!(close, "{polygon:?} at {p:?}: {d} {g:?} against {d0} {g0:?}");
            let (dx, _) = outline_distance(&edges, true, [Dual64::new(p[0], 1.0), Dual64::from(p[1])]);
            let (dy, _) = outline_distance(&edges, true, [Dual64::from(p[0]), Dual64::new(p[1], 1.0)]);
            assert!((dx.eps - g0[0]).abs() < 1e-9 && (dy.eps - g0[1]).abs() < 1e-9, "{polygon:?} at {p:?}");
            if d0 < 0.0 { inside += 1 } else { outside += 1 }
        }
        assert!(inside > 300 && outside > 300, "{polygon:?}: {inside} inside, {outside} outside");
    }
}

/// A thin plate's sample spheres touch its faces and sides and stay inside it.
#[test]
fn thin_plate_samples_fill_the_rim() {
    let square =
        [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let plate = Solid::plate(&square, 0.02, 0.01).unwrap();
    assert_eq!(plate.samples.len(), 4 * 49);
    for s in &plate.samples {
        let (d, _) = plate.signed_distance(&s.point_in_body);
        assert!((d + s.radius).abs() < 1e-12, "sample {s:?} at {d}");
    }
}
