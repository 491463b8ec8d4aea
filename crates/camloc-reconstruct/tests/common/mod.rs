//! Synthetic canonical 3D poses for tests and benches: a plausible 15-landmark skeleton with
//! per-subject limb lengths and random joint angles (half of the poses follow a walking cycle,
//! half are free poses), canonicalised as docs/conventions.md section 1 says (pelvis at the origin,
//! facing
//! -x, right side towards +y, z up, metres).

#![allow(dead_code)] // Each test binary uses a different part of this module.

use std::sync::OnceLock;

use camloc_geometry::{Matrix3, Vector3, look_at_origin, rotation_about_axis, sphere_point};
use camloc_reconstruct::{
    BasisConfig, BasisKind, PoseBasis, ReconstructConfig, Refinement, sum_squared_limb_lengths,
};
use camloc_skeleton::{NUM_LANDMARKS, Pose3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Deterministic generator.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// Unit vectors of the canonical body: forward (-x), right (+y), up (+z).
const FORWARD: [f64; 3] = [-1.0, 0.0, 0.0];
const RIGHT: [f64; 3] = [0.0, 1.0, 0.0];
const UP: [f64; 3] = [0.0, 0.0, 1.0];

fn v(a: [f64; 3]) -> Vector3 {
    Vector3::from(a)
}

/// Joint angles of one pose, radians.
struct Angles {
    /// Hip flexion (+ = thigh forward), left and right.
    hip_flex: [f64; 2],
    /// Hip abduction (+ = thigh outward).
    hip_abd: [f64; 2],
    /// Knee flexion (+ = shin backward), >= 0.
    knee: [f64; 2],
    /// Arm elevation away from hanging down, >= 0.
    arm_elev: [f64; 2],
    /// Arm swing direction: 0 = forward, pi/2 = outward.
    arm_dir: [f64; 2],
    /// Elbow flexion >= 0 and the roll of its bending plane about the upper arm.
    elbow: [f64; 2],
    elbow_roll: [f64; 2],
    /// Torso lean forward and sideways, twist of the shoulders about the torso axis.
    lean: f64,
    side: f64,
    twist: f64,
    /// Head pitch forward.
    head: f64,
}

fn walking(rng: &mut ChaCha8Rng) -> Angles {
    let p = rng.random_range(0.0..std::f64::consts::TAU);
    let n = |rng: &mut ChaCha8Rng, s: f64| rng.random_range(-s..s);
    let swing = deg(25.0) * p.sin();
    Angles {
        hip_flex: [swing + n(rng, 0.1), -swing + n(rng, 0.1)],
        hip_abd: [deg(3.0) + n(rng, 0.05), deg(3.0) + n(rng, 0.05)],
        knee: [
            deg(8.0) + deg(45.0) * (p + 1.2).sin().max(0.0) + n(rng, 0.08).abs(),
            deg(8.0)
                + deg(45.0) * (p + 1.2 + std::f64::consts::PI).sin().max(0.0)
                + n(rng, 0.08).abs(),
        ],
        arm_elev: [
            (deg(20.0) * p.sin()).abs() + deg(5.0) + n(rng, 0.05).abs(),
            (deg(20.0) * p.sin()).abs() + deg(5.0) + n(rng, 0.05).abs(),
        ],
        arm_dir: [
            if p.sin() < 0.0 {
                0.2
            } else {
                std::f64::consts::PI - 0.2
            },
            if p.sin() > 0.0 {
                0.2
            } else {
                std::f64::consts::PI - 0.2
            },
        ],
        elbow: [deg(20.0) + n(rng, 0.2).abs(), deg(20.0) + n(rng, 0.2).abs()],
        elbow_roll: [n(rng, 0.3), n(rng, 0.3)],
        lean: deg(5.0) + n(rng, 0.08),
        side: n(rng, 0.05),
        twist: deg(8.0) * p.sin() + n(rng, 0.05),
        head: n(rng, 0.2),
    }
}

fn free(rng: &mut ChaCha8Rng) -> Angles {
    let mut u = |lo: f64, hi: f64| rng.random_range(deg(lo)..deg(hi));
    Angles {
        hip_flex: [u(-30.0, 100.0), u(-30.0, 100.0)],
        hip_abd: [u(-5.0, 40.0), u(-5.0, 40.0)],
        knee: [u(0.0, 130.0), u(0.0, 130.0)],
        arm_elev: [u(0.0, 170.0), u(0.0, 170.0)],
        arm_dir: [u(-20.0, 150.0), u(-20.0, 150.0)],
        elbow: [u(0.0, 145.0), u(0.0, 145.0)],
        elbow_roll: [u(-60.0, 60.0), u(-60.0, 60.0)],
        lean: u(-15.0, 50.0),
        side: u(-15.0, 15.0),
        twist: u(-35.0, 35.0),
        head: u(-20.0, 40.0),
    }
}

/// One canonical pose: walking with probability 1/2, otherwise free.
pub fn random_pose(rng: &mut ChaCha8Rng) -> Pose3 {
    let angles = if rng.random_bool(0.5) {
        walking(rng)
    } else {
        free(rng)
    };
    let size = rng.random_range(0.85..1.15);
    let mut len = |base: f64| base * size * rng.random_range(0.95..1.05);
    let (pelvis_half, thigh, shin) = (len(0.10), len(0.42), len(0.41));
    let (torso, neck_head, shoulder_half) = (len(0.50), len(0.22), len(0.18));
    let (upper_arm, forearm) = (len(0.29), len(0.26));
    skeleton(
        &angles,
        [
            pelvis_half,
            thigh,
            shin,
            torso,
            neck_head,
            shoulder_half,
            upper_arm,
            forearm,
        ],
    )
}

/// Builds the landmarks from angles and lengths, then canonicalises the heading.
fn skeleton(a: &Angles, l: [f64; 8]) -> Pose3 {
    let [
        pelvis_half,
        thigh,
        shin,
        torso,
        neck_head,
        shoulder_half,
        upper_arm,
        forearm,
    ] = l;
    let (fwd, right, up) = (v(FORWARD), v(RIGHT), v(UP));
    let mut p = [Vector3::zeros(); NUM_LANDMARKS];
    // Legs: index 0 = left (-y), 1 = right (+y).
    for side in 0..2 {
        let out = if side == 0 { -right } else { right };
        let hip = out * pelvis_half - up * 0.05;
        // Thigh: hang down, flex forward about the lateral axis, abduct outward.
        let flex = rotation_about_axis(right, -a.hip_flex[side]);
        let abd = rotation_about_axis(
            fwd,
            if side == 0 {
                a.hip_abd[side]
            } else {
                -a.hip_abd[side]
            },
        );
        let thigh_dir = abd * flex * -up;
        let lateral = abd * right;
        let shin_dir = rotation_about_axis(lateral, a.knee[side]) * thigh_dir;
        let knee = hip + thigh_dir * thigh;
        let ankle = knee + shin_dir * shin;
        let base = 1 + 3 * side;
        p[base] = hip;
        p[base + 1] = knee;
        p[base + 2] = ankle;
    }
    // Torso: lean forward and sideways, shoulders twisted about the torso axis.
    let torso_rot = rotation_about_axis(fwd, a.side) * rotation_about_axis(right, -a.lean);
    let axis = torso_rot * up;
    let neck = axis * torso;
    p[7] = neck;
    p[8] = neck + rotation_about_axis(torso_rot * right, -a.head) * axis * neck_head;
    let twist = rotation_about_axis(axis, a.twist) * torso_rot;
    let (t_fwd, t_right) = (twist * fwd, twist * right);
    for side in 0..2 {
        let out = if side == 0 { -t_right } else { t_right };
        let shoulder = neck + out * shoulder_half - axis * 0.03;
        let (ae, ad) = (a.arm_elev[side], a.arm_dir[side]);
        let upper_dir =
            (-axis * ae.cos() + (t_fwd * ad.cos() + out * ad.sin()) * ae.sin()).normalize();
        let bend_axis = rotation_about_axis(upper_dir, a.elbow_roll[side]) * upper_dir.cross(&out);
        let bend_axis = if bend_axis.norm() > 1e-9 {
            bend_axis
        } else {
            t_right
        };
        let fore_dir = rotation_about_axis(bend_axis, a.elbow[side]) * upper_dir;
        let elbow = shoulder + upper_dir * upper_arm;
        let base = 9 + 3 * side;
        p[base] = shoulder;
        p[base + 1] = elbow;
        p[base + 2] = elbow + fore_dir * forearm;
    }
    canonicalise(Pose3::new(p.map(Into::into)))
}

/// Rotates about z so that the horizontal part of (right_hip - left_hip) + (right_shoulder -
/// left_shoulder) points to +y, with the pelvis at the origin (docs/conventions.md section 1).
pub fn canonicalise(pose: Pose3) -> Pose3 {
    let q = |i: usize| v(pose.points[i]);
    let pelvis = q(0);
    let across = (q(4) - q(1)) + (q(12) - q(9));
    let heading = across.y.atan2(across.x); // angle of `across` from +x
    let turn = rotation_about_axis(v(UP), std::f64::consts::FRAC_PI_2 - heading);
    Pose3::new(pose.points.map(|p| (turn * (v(p) - pelvis)).into()))
}

/// `n` random canonical poses.
pub fn training_set(n: usize, seed: u64) -> Vec<Pose3> {
    let mut r = rng(seed);
    (0..n).map(|_| random_pose(&mut r)).collect()
}

/// A camera rotation looking at the origin from a random direction: azimuth anywhere,
/// elevation within +-`max_elevation_deg`.
pub fn random_rotation(rng: &mut ChaCha8Rng, max_elevation_deg: f64) -> Matrix3 {
    let az = rng.random_range(0.0..360.0);
    let el = rng.random_range(-max_elevation_deg..=max_elevation_deg);
    look_at_origin(sphere_point(az, el, 1.0)).expect("elevation is below the pole")
}

/// A pose inside the basis span: `mu + B w` with `w` drawn on the first `active` components
/// (scaled by their standard deviations) and then scaled by the positive factor that puts its
/// sum of squared limb lengths on `target`. Returns the pose and its full coefficient vector.
pub fn pose_in_span(
    basis: &PoseBasis,
    rng: &mut ChaCha8Rng,
    active: usize,
    target: f64,
) -> (Pose3, Vec<f64>) {
    let k = basis.n_components();
    let mut w = vec![0.0; k];
    for (j, wj) in w.iter_mut().enumerate().take(active) {
        *wj = basis.explained_variance()[j].sqrt() * rng.random_range(-1.5..1.5);
    }
    // f(t) = limb sum of mu + t B w is quadratic in t: recover it from three values.
    let f = |t: f64| {
        let scaled: Vec<f64> = w.iter().map(|x| x * t).collect();
        sum_squared_limb_lengths(&basis.pose(&scaled).unwrap()) - target
    };
    let (f0, f1, fm) = (f(0.0), f(1.0), f(-1.0));
    let (qa, qb, qc) = ((f1 + fm) / 2.0 - f0, (f1 - fm) / 2.0, f0);
    let disc = qb * qb - 4.0 * qa * qc;
    assert!(disc >= 0.0 && qa > 0.0, "constraint unreachable along w");
    let t = (-qb + disc.sqrt()) / (2.0 * qa);
    let w: Vec<f64> = w.iter().map(|x| x * t).collect();
    (basis.pose(&w).unwrap(), w)
}

/// The default pursuit without its priors (coefficient prior, limb symmetry, joint limits)
/// and without the skeleton refinement (its length prior): the plain projected matching
/// pursuit whose exact properties the tests check.
pub fn without_priors() -> ReconstructConfig {
    ReconstructConfig {
        coefficient_prior: 0.0,
        symmetry: false,
        joint_limits: false,
        refinement: Refinement {
            estimate_lengths: false,
            ..Refinement::default()
        },
        ..ReconstructConfig::default()
    }
}

/// 12 principal components of 2000 synthetic poses (seed 7), fitted once: small enough that a
/// pose on the first few is recovered exactly.
pub fn small_basis() -> &'static PoseBasis {
    static BASIS: OnceLock<PoseBasis> = OnceLock::new();
    BASIS.get_or_init(|| {
        PoseBasis::fit(
            &training_set(2000, 7),
            &BasisConfig {
                n_components: 12,
                kind: BasisKind::Pca,
                ..BasisConfig::default()
            },
        )
        .unwrap()
    })
}
