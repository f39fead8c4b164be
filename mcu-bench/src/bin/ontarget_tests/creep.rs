//! No creep at rest, on the target: the contact step on every surface, pressed 1 mm and held at a
//! tilted, twisted orientation for 20 000 ticks, renders bit for bit the same force, spin and
//! contact point every tick; then, with one wrist count of dither about a tangent axis and about
//! the normal, every second tick is back exactly (plane: every method; curved surfaces: exact).

use core::hint::black_box as bb;
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::state::ContactState;
use softfinger_core::contact::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
use softfinger_core::contact::{ContactInput, ContactModel};
use softfinger_core::{Libm, Math, Quat, Vec3};
use softfinger_mcu_bench::check::Checker;

fn held<M: Math, S: Surface>(c: &mut Checker, name: &str, surface: S, method: Method) {
    let params = ContactParams {
        method,
        ..ContactParams::DEFAULT
    };
    let q = Quat::from_rotation_vector::<Libm>(Vec3::new(0.3, -0.2, 0.1)).0;
    let Ok(mut m) = ContactModel::<M, S>::new(params, surface, q, 1e-4) else {
        c.ok(name, false);
        return;
    };
    let probe = surface.contact_point() + surface.normal() * (params.fingertip_radius_m - 0.001);
    let input = |q| ContactInput {
        q,
        probe_m: probe,
        probe_vel: Vec3::ZERO,
    };
    for _ in 0..5 {
        m.contact_step(&input(q));
    }
    let first = m.contact_step(&input(q));
    let mut same = first.state == ContactState::Rolling;
    for _ in 0..20_000 {
        let o = m.contact_step(&bb(input(q)));
        same &= o.force_n == first.force_n
            && o.spin_rad == first.spin_rad
            && o.object_point_m == first.object_point_m;
    }
    c.ok(name, same);
    if method == Method::PaperVerbatim {
        return; // its spurious spins slide the contact (friction), see the host tests
    }
    let count = core::f32::consts::TAU / 4096.0;
    let tilt = q * Quat::from_axis_angle::<Libm>(Vec3::X, count);
    let twist = q * Quat::from_axis_angle::<Libm>(Vec3::Z, count);
    let mut back = true;
    for k in 0..4000 {
        let o = m.contact_step(&bb(input([tilt, q, twist, q][k % 4])));
        if k % 2 == 1 {
            back &= o.spin_rad == first.spin_rad
                && o.object_point_m == first.object_point_m
                && o.tau_n_nm == first.tau_n_nm;
        }
    }
    c.ok(name, back);
}

/// The checks for backend `M`.
pub fn checks<M: Math>(c: &mut Checker) {
    held::<M, _>(c, "no creep: plane, exact", Plane::default(), Method::Exact);
    held::<M, _>(c, "no creep: plane, rpy", Plane::default(), Method::Rpy);
    held::<M, _>(
        c,
        "no creep: plane, paper",
        Plane::default(),
        Method::PaperVerbatim,
    );
    held::<M, _>(c, "no creep: sphere", Sphere::new(0.05), Method::Exact);
    held::<M, _>(c, "no creep: bowl", Bowl::new(0.05), Method::Exact);
    held::<M, _>(c, "no creep: cylinder", Cylinder::new(0.05), Method::Exact);
}
