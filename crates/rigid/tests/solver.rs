//! The contact impact inclusion: closed-form impacts (sphere bounce, sticking and sliding,
//! eccentric rod), the contact laws and energy on random bodies, warm start, a resting box.
#![allow(clippy::unwrap_used)]

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use rockfall_rigid::math::{M3, Quat, V3, tangent_basis};
use rockfall_rigid::rotation::inverse_inertia_world;
use rockfall_rigid::solver::{Contact, InverseMass, SolveReport, SolverSettings, Velocity, solve};

/// A rigid body for the tests: mass, principal inertia and orientation.
#[derive(Debug, Clone)]
struct Body {
    mass_kg: f64,
    inertia_kgm2: V3,
    q: Quat,
}

impl Body {
    fn minv(&self) -> InverseMass {
        InverseMass {
            inv_mass_per_kg: 1.0 / self.mass_kg,
            inv_inertia_world: inverse_inertia_world(self.q, self.inertia_kgm2),
        }
    }

    /// Kinetic energy ½ m v² + ½ ωᵀ I_w ω, J.
    fn energy_j(&self, u: Velocity) -> f64 {
        let r = M3::from_quat(self.q);
        let inertia_world = r * M3::from_diagonal(self.inertia_kgm2) * r.transpose();
        0.5 * self.mass_kg * u.v_ms.length_squared() + 0.5 * u.w_rads.dot(inertia_world * u.w_rads)
    }

    fn solve(&self, u_b: Velocity, u_free: Velocity, contacts: &mut [Contact]) -> Velocity {
        let (u_e, report) = solve(&self.minv(), u_b, u_free, contacts, &tight());
        assert!(report.converged, "{report:?}");
        u_e
    }
}

/// Settings for closed-form checks: converge to round-off.
fn tight() -> SolverSettings {
    SolverSettings {
        tolerance_ms: 1e-13,
        max_iterations: 100_000,
        ..SolverSettings::default()
    }
}

fn velocity(v_ms: V3, w_rads: V3) -> Velocity {
    Velocity { v_ms, w_rads }
}

/// Solid sphere of radius 1 m, mass 2 kg (Θ = 2/5 m R²).
const R: f64 = 1.0;
const SPHERE: Body = Body {
    mass_kg: 2.0,
    inertia_kgm2: V3::splat(0.8),
    q: Quat::IDENTITY,
};

fn ground_contact(mu: f64, eps_n: f64, eps_t: f64) -> Contact {
    Contact::new(V3::new(0.0, 0.0, -R), V3::Z, mu, eps_n, eps_t)
}

#[test]
fn sphere_bounces_with_restitution() {
    for (eps_n, rebound) in [(0.5, 1.5), (1.0, 3.0), (0.0, 0.0)] {
        let u = velocity(V3::new(0.0, 0.0, -3.0), V3::ZERO);
        let mut contacts = [ground_contact(0.5, eps_n, 0.0)];
        let u_e = SPHERE.solve(u, u, &mut contacts);
        assert!((u_e.v_ms - V3::new(0.0, 0.0, rebound)).length() < 1e-9);
        assert!(u_e.w_rads.length() < 1e-9);
        let p_n = SPHERE.mass_kg * (3.0 + rebound);
        assert!((contacts[0].percussion_ns - V3::new(p_n, 0.0, 0.0)).length() < 1e-9);
    }
}

#[test]
fn sliding_sphere_sticks_with_large_friction() {
    let u = velocity(V3::new(2.0, -1.0, -3.0), V3::new(0.3, 0.0, 0.0));
    let mut contacts = [ground_contact(10.0, 0.5, 0.0)];
    let u_e = SPHERE.solve(u, u, &mut contacts);
    let v_contact = u_e.at(contacts[0].arm_m);
    assert!((v_contact.z - 1.5).abs() < 1e-9);
    assert!(
        v_contact.truncate().length() < 1e-9,
        "the contact still slips: {v_contact}"
    );
}

/// μ = 0.1, ε_N = 0.5: P_N = m (1 + ε_N) 3, the friction percussion −μ P_N along the slip,
/// Δv_x = −μ P_N/m, Δω_y = R μ P_N/Θ, so the slip drops by μ P_N (1/m + R²/Θ) < 2 m/s.
#[test]
fn sliding_sphere_slides_with_small_friction() {
    let mu = 0.1;
    let u = velocity(V3::new(2.0, 0.0, -3.0), V3::ZERO);
    let mut contacts = [ground_contact(mu, 0.5, 0.0)];
    let u_e = SPHERE.solve(u, u, &mut contacts);
    let m = SPHERE.mass_kg;
    let theta = SPHERE.inertia_kgm2.x;
    let p_n = m * 1.5 * 3.0;
    let (t1, t2) = tangent_basis(V3::Z);
    let p = contacts[0].percussion_ns;
    let p_t_world = t1 * p.y + t2 * p.z;
    assert!((p.x - p_n).abs() < 1e-9);
    assert!((p_t_world - V3::new(-mu * p_n, 0.0, 0.0)).length() < 1e-9);
    let v_expected = V3::new(2.0 - mu * p_n / m, 0.0, 1.5);
    let w_expected = V3::new(0.0, R * mu * p_n / theta, 0.0);
    assert!((u_e.v_ms - v_expected).length() < 1e-9);
    assert!((u_e.w_rads - w_expected).length() < 1e-9);
    let slip = u_e.at(contacts[0].arm_m).x;
    assert!((slip - (2.0 - mu * p_n * (1.0 / m + R * R / theta))).abs() < 1e-9);
    assert!(slip > 0.0);
}

/// Box 2 × 0.2 × 0.2 m (a rod along x), 3 kg, tilted; one contact at the end of the rod.
fn rod() -> Body {
    let (m, a, b, c) = (3.0, 2.0, 0.2, 0.2);
    Body {
        mass_kg: m,
        inertia_kgm2: V3::new(b * b + c * c, a * a + c * c, a * a + b * b) * (m / 12.0),
        q: Quat::from_axis_angle(V3::new(0.2, 1.0, 0.3).normalize(), 0.4),
    }
}

/// ε_N = 1, μ = 0: P_N = −2 γ⁻_N / G_nn, so γ⁺_N = −γ⁻_N and ½ m v² + ½ ωᵀIω is conserved.
#[test]
fn eccentric_rod_impact_is_elastic() {
    let body = rod();
    let arm = body.q * V3::new(1.0, 0.1, -0.1);
    let n = V3::new(0.1, -0.2, 1.0).normalize();
    let u = velocity(V3::new(0.5, 0.2, -3.0), V3::new(1.0, -2.0, 0.5));
    let mut contacts = [Contact::new(arm, n, 0.0, 1.0, 0.0)];
    let u_e = body.solve(u, u, &mut contacts);

    let gamma_minus = n.dot(u.at(arm));
    let rxn = arm.cross(n);
    let g_nn = 1.0 / body.mass_kg + rxn.dot(body.minv().inv_inertia_world * rxn);
    assert!((contacts[0].percussion_ns.x + 2.0 * gamma_minus / g_nn).abs() < 1e-9);
    assert!((n.dot(u_e.at(arm)) + gamma_minus).abs() < 1e-9);
    let (e_b, e_e) = (body.energy_j(u), body.energy_j(u_e));
    assert!((e_e - e_b).abs() < 1e-9 * e_b, "{e_b} J → {e_e} J");
}

/// Box 1 × 0.6 × 0.4 m, 5 kg, flat on the ground z = 0 with its four lower corners in contact.
fn resting_box() -> (Body, [Contact; 4]) {
    let (m, h) = (5.0, V3::new(0.5, 0.3, 0.2));
    let body = Body {
        mass_kg: m,
        inertia_kgm2: V3::new(
            h.y * h.y + h.z * h.z,
            h.x * h.x + h.z * h.z,
            h.x * h.x + h.y * h.y,
        ) * (m / 3.0),
        q: Quat::IDENTITY,
    };
    let corner =
        |sx: f64, sy: f64| Contact::new(V3::new(sx * h.x, sy * h.y, -h.z), V3::Z, 0.5, 0.0, 0.0);
    (
        body,
        [
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
        ],
    )
}

const G: f64 = 9.81;
const DT: f64 = 1e-3;

/// Solves the resting box with `contacts` under u_free = −g dt: the box stays at rest and the
/// contacts carry its weight, Σ P_N = m g dt.
fn assert_box_stays_at_rest(body: &Body, contacts: &mut [Contact]) {
    let rest = velocity(V3::ZERO, V3::ZERO);
    let u_free = velocity(V3::new(0.0, 0.0, -G * DT), V3::ZERO);
    let u_e = body.solve(rest, u_free, contacts);
    assert!(
        u_e.v_ms.length() < 1e-10 && u_e.w_rads.length() < 1e-10,
        "{u_e:?}"
    );
    let total: V3 = contacts.iter().map(|c| c.percussion_ns).sum();
    assert!((total.x - body.mass_kg * G * DT).abs() < 1e-10);
}

#[test]
fn resting_box_stays_at_rest() {
    let (body, mut contacts) = resting_box();
    assert_box_stays_at_rest(&body, &mut contacts);
}

/// Each corner three times: 12 contacts, more than the solver caches, so the frames of the last
/// ones are recomputed every sweep.
#[test]
fn resting_box_with_more_contacts_than_cached() {
    let (body, corners) = resting_box();
    let mut contacts: Vec<Contact> = corners.iter().cycle().take(12).copied().collect();
    assert_box_stays_at_rest(&body, &mut contacts);
}

#[test]
fn warm_start_converges_in_fewer_iterations() {
    let (body, mut contacts) = resting_box();
    let u_b = velocity(V3::new(0.3, 0.1, -0.2), V3::new(0.2, -0.4, 0.1));
    let u_free = velocity(u_b.v_ms - V3::new(0.0, 0.0, G * DT), u_b.w_rads);
    let run = |contacts: &mut [Contact], warm_start: bool| -> SolveReport {
        let settings = SolverSettings {
            warm_start,
            ..SolverSettings::default()
        };
        solve(&body.minv(), u_b, u_free, contacts, &settings).1
    };
    let cold = run(&mut contacts, false);
    let warm = run(&mut contacts, true);
    assert!(cold.converged && warm.converged);
    assert!(
        warm.iterations < cold.iterations,
        "cold {cold:?}, warm {warm:?}"
    );
    // zeroing: without warm start the stored percussions are ignored
    let again = run(&mut contacts, false);
    assert_eq!(again, cold);
}

/// A contact at the centre of mass (zero arm, μ = 0, ε = 1), a side wall the rock moves away
/// from and a contact without a normal: the wall separates (P = 0), the first contact bounces the
/// rock, the third does nothing.
#[test]
fn zero_arm_separating_and_degenerate_contacts() {
    let u = velocity(V3::new(1.0, 0.0, -2.0), V3::new(0.0, 3.0, 0.0));
    let mut contacts = [
        Contact::new(V3::ZERO, V3::Z, 0.0, 1.0, 1.0),
        Contact::new(V3::new(-1.0, 0.0, 0.0), V3::X, 0.3, 0.0, 0.0),
        // a degenerate (zero) normal has no contact frame and is ignored
        Contact::new(V3::new(0.0, 0.0, -1.0), V3::ZERO, 0.3, 0.0, 0.0),
    ];
    let u_e = SPHERE.solve(u, u, &mut contacts);
    assert!((u_e.v_ms - V3::new(1.0, 0.0, 2.0)).length() < 1e-12);
    assert_eq!(u_e.w_rads, u.w_rads);
    assert_eq!(contacts[1].percussion_ns, V3::ZERO);
    let (u_none, report) = solve(&SPHERE.minv(), u, u, &mut [], &SolverSettings::default());
    assert_eq!((u_none, report.iterations), (u, 0));
}

/// The Newton law and Coulomb's law at a solved contact, within `tol` (m/s, N s scale 1).
fn assert_contact_laws(c: &Contact, u_b: Velocity, u_e: Velocity, tol: f64) {
    let (t1, t2) = tangent_basis(c.normal);
    let (g_b, g_e) = (u_b.at(c.arm_m), u_e.at(c.arm_m));
    let xi = |d: V3, eps: f64| d.dot(g_e) + eps * d.dot(g_b);
    let (xi_n, xi_t) = (
        xi(c.normal, c.eps_n),
        V3::new(0.0, xi(t1, c.eps_t), xi(t2, c.eps_t)),
    );
    let p = c.percussion_ns;
    let p_t = V3::new(0.0, p.y, p.z);
    assert!(p.x >= 0.0);
    assert!(p_t.length() <= c.mu * p.x * (1.0 + 1e-9) + 1e-15, "{c:?}");
    assert!(xi_n >= -tol, "ξ_N = {xi_n}");
    assert!(
        (p.x * xi_n).abs() <= tol * (1.0 + p.x),
        "P_N ξ_N = {}",
        p.x * xi_n
    );
    // −ξ_T ∈ N_disc(P_T): ξ_T = 0 inside the disc, ξ_T = −|ξ_T| P_T/|P_T| on its rim
    if p_t.length() < c.mu * p.x * (1.0 - 1e-6) {
        assert!(xi_t.length() <= tol, "sticking with ξ_T = {xi_t}");
    } else if p_t.length() > 0.0 {
        assert!(
            (xi_t + xi_t.length() * p_t / p_t.length()).length() <= tol * (1.0 + xi_t.length())
        );
    }
}

fn unit_quat() -> impl Strategy<Value = Quat> {
    (
        prop::array::uniform3(-1.0..1.0_f64),
        0.0..std::f64::consts::PI,
    )
        .prop_filter("axis", |(a, _)| V3::from_array(*a).length() > 0.1)
        .prop_map(|(a, angle)| Quat::from_axis_angle(V3::from_array(a).normalize(), angle))
}

fn vec3(range: f64) -> impl Strategy<Value = V3> {
    prop::array::uniform3(-range..range).prop_map(V3::from_array)
}

/// A contact with a random arm (|r_i| ≤ √3 m) and a normal tilted by at most `max_tilt` (rad)
/// from +z; μ ∈ [0, 1.5], ε ∈ [0, 1] unless `plastic`.
fn contact(max_tilt: f64, plastic: bool) -> impl Strategy<Value = Contact> {
    let angles = (0.0..max_tilt, 0.0..std::f64::consts::TAU);
    let laws = (0.0..1.5_f64, 0.0..=1.0_f64, 0.0..=1.0_f64);
    (vec3(1.0), angles, laws).prop_map(move |(arm, (tilt, azimuth), (mu, eps_n, eps_t))| {
        let normal = V3::new(
            tilt.sin() * azimuth.cos(),
            tilt.sin() * azimuth.sin(),
            tilt.cos(),
        );
        let (eps_n, eps_t) = if plastic { (0.0, 0.0) } else { (eps_n, eps_t) };
        Contact::new(arm, normal, mu, eps_n, eps_t)
    })
}

/// Any normal with a positive z component.
const ANY_TILT: f64 = 1.5;
/// Normals within 30° of +z: with μ ≤ 1.5 (cone half-angle ≤ 56.3°) every friction cone lies in
/// the upper half-space, so `Σ W_i P_i = 0` only for P = 0 and the percussions are bounded. With
/// opposing cones a rock can wedge: the percussions then grow without bound along the null space
/// of W (u_E still converges), which no percussion-based law check can follow.
const NO_WEDGING_TILT: f64 = std::f64::consts::FRAC_PI_6;

fn body() -> impl Strategy<Value = Body> {
    let inertia = prop::array::uniform3(0.1..2.0_f64);
    (0.5..100.0_f64, inertia, unit_quat()).prop_map(|(m, k, q)| Body {
        mass_kg: m,
        inertia_kgm2: V3::from_array(k) * m,
        q,
    })
}

/// Solves a random impact (u_B = u_free) to 1e-11 m/s; `None` when it does not converge.
fn solve_random(body: &Body, contacts: &mut [Contact], u: Velocity) -> Option<Velocity> {
    let settings = SolverSettings {
        tolerance_ms: 1e-11,
        max_iterations: 20_000,
        ..SolverSettings::default()
    };
    let (u_e, report) = solve(&body.minv(), u, u, contacts, &settings);
    report.converged.then_some(u_e)
}

/// The laws hold at every contact, and the energy does not grow with one contact when
/// ε_N ≤ ε_T or μ = 0, or with several when ε = 0. Newton's law with ε_N > ε_T can add energy
/// even at a single frictional contact (Kane's paradox, pinned by
/// `newton_law_with_eps_n_above_eps_t_can_add_energy`), and with ε > 0 at several contacts.
fn check_random_impact(body: &Body, contacts: &[Contact], u: Velocity, u_e: Velocity) {
    let tol = 1e-8 * (1.0 + u.v_ms.length() + u.w_rads.length());
    for c in contacts {
        assert_contact_laws(c, u, u_e, tol);
    }
    let (e_b, e_e) = (body.energy_j(u), body.energy_j(u_e));
    let dissipative = match contacts {
        [c] => c.eps_n <= c.eps_t || c.mu == 0.0,
        _ => contacts.iter().all(|c| c.eps_n == 0.0 && c.eps_t == 0.0),
    };
    if dissipative {
        assert!(e_e <= e_b * (1.0 + 1e-9) + 1e-12, "{e_b} J → {e_e} J");
    }
}

/// Kane's paradox (Glocker 2013, "Energetic consistency conditions for standard impacts, Part I",
/// Multibody Syst. Dyn. 29): with ε_N > ε_T = 0 the Newton-type law gains energy at this single
/// frictional contact although every law holds. Found by the property test; seen in 17 of 20 000
/// random one-contact impacts with ε_T = 0 (up to +38 %), never with ε_N ≤ ε_T.
#[test]
fn newton_law_with_eps_n_above_eps_t_can_add_energy() {
    let body = Body {
        mass_kg: 0.5,
        inertia_kgm2: V3::new(0.0876006702862666, 0.05, 0.05),
        q: Quat::from_xyzw(
            0.5752700183497501,
            0.7135333866593054,
            0.0,
            0.3999181317599643,
        ),
    };
    let arm = V3::new(-0.805490529016265, 0.0, -0.266541620279147);
    let normal = V3::new(0.04355915908228649, 0.7164501344569708, 0.696277103240249);
    let mut contacts = [Contact::new(
        arm,
        normal,
        0.2816732121041375,
        0.9588687634009296,
        0.0,
    )];
    let u = velocity(
        V3::new(1.0782981060990708, -4.9394908429830915, -3.8087045182072456),
        V3::new(-3.8318593401779153, 0.0, 0.0),
    );
    let u_e = body.solve(u, u, &mut contacts);
    assert_contact_laws(&contacts[0], u, u_e, 1e-9);
    let (e_b, e_e) = (body.energy_j(u), body.energy_j(u_e));
    assert!(e_e > 1.005 * e_b, "{e_b} J → {e_e} J");
    // the same impact with ε_T = ε_N dissipates
    contacts[0].eps_t = contacts[0].eps_n;
    let u_e = body.solve(u, u, &mut contacts);
    assert!(body.energy_j(u_e) <= e_b);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn one_contact_obeys_the_laws_and_dissipates(
        body in body(), mut c in contact(ANY_TILT, false), v in vec3(5.0), w in vec3(5.0),
    ) {
        let u = velocity(v, w);
        let u_e = solve_random(&body, std::slice::from_mut(&mut c), u);
        prop_assert!(u_e.is_some(), "no convergence");
        check_random_impact(&body, &[c], u, u_e.unwrap());
    }

    #[test]
    fn several_contacts_obey_the_laws(
        body in body(), plastic in any::<bool>(),
        contacts in prop::collection::vec(contact(NO_WEDGING_TILT, false), 2..=4),
        v in vec3(5.0), w in vec3(5.0),
    ) {
        let mut contacts = contacts;
        if plastic {
            contacts.iter_mut().for_each(|c| (c.eps_n, c.eps_t) = (0.0, 0.0));
        }
        let u = velocity(v, w);
        let u_e = solve_random(&body, &mut contacts, u);
        // rare slow or cycling cases are counted by `random_impacts_rarely_fail_to_converge`
        prop_assume!(u_e.is_some());
        check_random_impact(&body, &contacts, u, u_e.unwrap());
    }
}

/// Prox Gauss–Seidel on several frictional contacts has no convergence guarantee (Coulomb's law
/// is not associated); pin how rarely it fails within 20 000 sweeps on the random impacts above.
#[test]
fn random_impacts_rarely_fail_to_converge() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let cases = (
        body(),
        prop::collection::vec(contact(NO_WEDGING_TILT, false), 1..=4),
        vec3(5.0),
        vec3(5.0),
    );
    let total = 1000;
    let failures = (0..total)
        .filter(|_| {
            let (body, mut contacts, v, w) = cases.new_tree(&mut runner).unwrap().current();
            solve_random(&body, &mut contacts, velocity(v, w)).is_none()
        })
        .count();
    assert!(
        failures * 200 <= total,
        "{failures} of {total} did not converge"
    );
}
