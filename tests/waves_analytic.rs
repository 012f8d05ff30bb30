//! The wave simulation (paper §5, eq. 1) against answers known in closed form: a spherical
//! harmonic's frequency, energy conservation, a constant field at rest, a pulse's finite speed.

use glam::{DVec3, Vec3};
use surftrack::apps::waves::{Laplacian, WaveParameters, WaveState, advance};
use surftrack::mesh::IndexedMesh;

fn undamped(speed: f64, min_substeps: usize) -> WaveParameters {
    WaveParameters {
        speed,
        damping: 0.0,
        min_substeps,
    }
}

/// `Σ m h Y / Σ m Y²`: how much of the mode `y` the field holds.
fn projection(laplacian: &Laplacian, h: &[f64], y: &[f64]) -> f64 {
    let m = laplacian.mass();
    let num: f64 = (0..h.len()).map(|i| m[i] * h[i] * y[i]).sum();
    let den: f64 = (0..h.len()).map(|i| m[i] * y[i] * y[i]).sum();
    num / den
}

/// The angular frequency of `a(t)` from its first and third downward/upward zero crossings.
fn measured_frequency(samples: &[(f64, f64)]) -> f64 {
    let crossings: Vec<f64> = samples
        .windows(2)
        .filter(|w| (w[0].1 > 0.0) != (w[1].1 > 0.0))
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1))
        .collect();
    assert!(crossings.len() >= 3, "{} zero crossings", crossings.len());
    2.0 * std::f64::consts::PI / (crossings[2] - crossings[0])
}

/// A real spherical harmonic of degree `l`, as a function of the unit direction.
type Mode = fn(DVec3) -> f64;

#[test]
fn a_spherical_harmonic_oscillates_at_its_analytic_frequency() {
    let radius = 1.5;
    let sphere = IndexedMesh::icosphere(Vec3::ZERO, radius as f32, 5);
    let laplacian = Laplacian::of(&sphere);
    let speed = 0.8;
    let modes: [(u32, Mode); 2] = [
        (2, |p| 3.0 * p.z * p.z - 1.0),
        (3, |p| p.x * (5.0 * p.z * p.z - 1.0)),
    ];
    for (l, mode) in modes {
        let y: Vec<f64> = sphere
            .positions
            .iter()
            .map(|p| mode(p.as_dvec3().normalize()))
            .collect();
        let mut state = WaveState::rest(y.len());
        state.height = y.clone();
        let lf = f64::from(l);
        let analytic = speed * (lf * (lf + 1.0)).sqrt() / radius;
        let period = 2.0 * std::f64::consts::PI / analytic;
        let dt = period / 400.0;
        let mut samples = vec![(0.0, 1.0)];
        for k in 1..=600 {
            advance(&laplacian, &mut state, &undamped(speed, 1), dt);
            samples.push((k as f64 * dt, projection(&laplacian, &state.height, &y)));
        }
        let measured = measured_frequency(&samples);
        let error = (measured - analytic).abs() / analytic;
        println!(
            "l = {l}: ω measured {measured:.5}, analytic {analytic:.5}, error {:.3}% ({} vertices)",
            100.0 * error,
            y.len()
        );
        assert!(error < 0.02, "l = {l}: relative error {error}");
    }
}

#[test]
fn undamped_energy_stays_within_one_percent_over_200_steps() {
    let sphere = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 4);
    let laplacian = Laplacian::of(&sphere);
    let speed = 1.0;
    let mut state = WaveState::rest(sphere.positions.len());
    for (h, p) in state.height.iter_mut().zip(&sphere.positions) {
        let p = p.as_dvec3();
        *h = (-(p - DVec3::Z).length_squared() / 0.1).exp() + 0.3 * p.x * p.y;
    }
    let parameters = undamped(speed, 1);
    let step = 0.5 / (speed * laplacian.max_eigenvalue_bound().sqrt());
    let start = state.energy(&laplacian, speed);
    let mut worst = 0.0f64;
    for _ in 0..200 {
        assert_eq!(advance(&laplacian, &mut state, &parameters, step), 1);
        let drift = (state.energy(&laplacian, speed) - start).abs() / start;
        worst = worst.max(drift);
    }
    println!("energy drift over 200 steps: at most {:.4}%", 100.0 * worst);
    assert!(worst < 0.01, "energy drifted by {worst}");
}

#[test]
fn a_constant_field_stays_constant() {
    let torus = IndexedMesh::torus(1.0, 0.35, 40, 16);
    let laplacian = Laplacian::of(&torus);
    let mut state = WaveState::rest(torus.positions.len());
    state.height.fill(0.7);
    let steps = advance(&laplacian, &mut state, &undamped(2.0, 100), 1.0);
    assert!(steps >= 100);
    let worst = state
        .height
        .iter()
        .map(|h| (h - 0.7).abs())
        .chain(state.velocity.iter().map(|v| v.abs()))
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-12, "moved by {worst}");
}

#[test]
fn a_pulse_stays_zero_beyond_the_wave_front() {
    let sphere = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 5);
    let laplacian = Laplacian::of(&sphere);
    let edge = f64::from(sphere.mean_edge_length());
    let speed = 1.0;
    let width = 4.0 * edge;
    let geodesic = |p: &Vec3| {
        p.as_dvec3()
            .normalize()
            .dot(DVec3::Z)
            .clamp(-1.0, 1.0)
            .acos()
    };
    let mut state = WaveState::rest(sphere.positions.len());
    for (h, p) in state.height.iter_mut().zip(&sphere.positions) {
        *h = (-(geodesic(p) / width).powi(2)).exp();
    }
    let mut elapsed = 0.0;
    for t in [0.15, 0.3, 0.45] {
        advance(&laplacian, &mut state, &undamped(speed, 1), t - elapsed);
        elapsed = t;
        let front = speed * t + 3.0 * width + 2.0 * edge;
        let (mut outside, mut inside) = (0.0f64, 0.0f64);
        for (h, p) in state.height.iter().zip(&sphere.positions) {
            if geodesic(p) > front {
                outside = outside.max(h.abs());
            } else {
                inside = inside.max(h.abs());
            }
        }
        println!("t = {t}: largest |h| beyond c·t + 3σ + 2Δ: {outside:.2e}, within: {inside:.3}");
        assert!(outside < 1e-4, "t = {t}: {outside} beyond the front");
        assert!(inside > 0.05, "t = {t}: the pulse vanished ({inside})");
    }
}
