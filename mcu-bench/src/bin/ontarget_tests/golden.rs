//! Golden values of the math checks (kernels, rotations, decompositions, rolling), per backend:
//! the f32 bits of every value their `close*` checks receive, in order, and each value's
//! distance from its closed form as measured on the target. Written by
//! `scripts/mcu-bench --record-golden`; do not edit by hand.

pub const LIBM: &[u32] = &[
    0x3f000000, // sin(pi/6) = 1/2: off by 0
    0x3f800000, // sin(pi/2) = 1: off by 0
    0xbf3504f3, // sin(-pi/4) = -sqrt2/2: off by 0
    0x00000000, // sin(0) = 0: off by 0
    0x3effffff, // cos(pi/3) = 1/2: off by 2.98e-08
    0x3f800000, // cos(0) = 1: off by 0
    0xbf800000, // cos(pi) = -1: off by 0
    0xbf000001, // cos(-2pi/3) = -1/2: off by 5.96e-08
    0x3f000000, // sin_cos(pi/6) = (1/2, sqrt3/2): off by 0
    0x3f5db3d7, // sin_cos(pi/6) = (1/2, sqrt3/2): off by 0
    0xbf3504f3, // sin_cos(-3pi/4): off by 0
    0xbf3504f3, // sin_cos(-3pi/4): off by 0
    0x3f000005, // sin(pi/6 + 16 pi) = 1/2: off by 2.98e-07
    0x3f490fdb, // atan2(1, 1) = pi/4: off by 0
    0x4016cbe4, // atan2(1, -1) = 3pi/4: off by 0
    0xc016cbe4, // atan2(-1, -1) = -3pi/4: off by 0
    0xbf490fdb, // atan2(-1, 1) = -pi/4: off by 0
    0x3f860a92, // atan2(sqrt3, 1) = pi/3: off by 0
    0x3fc90fdb, // atan2(1, 0) = pi/2: off by 0
    0xbfc90fdb, // atan2(-1, 0) = -pi/2: off by 0
    0x00000000, // atan2(0, 1) = 0: off by 0
    0x40490fdb, // atan2(+0, -1) = pi: off by 0
    0x40000000, // sqrt of a known square: off by 0
    0x3f000000, // sqrt of a known square: off by 0
    0x3fb504f3, // sqrt of a known square: off by 0
    0x453b8000, // sqrt of a known square: off by 0
    0xb33bbd2e, // rodrigues 90 deg about z maps x to y: off by 4.37e-08
    0x3f800000, // rodrigues 90 deg about z maps x to y: off by 4.37e-08
    0x00000000, // rodrigues 90 deg about z maps x to y: off by 4.37e-08
    0xbf800000, // rodrigues 90 deg about z maps y to -x: off by 4.37e-08
    0xb33bbd2e, // rodrigues 90 deg about z maps y to -x: off by 4.37e-08
    0x00000000, // rodrigues 90 deg about z maps y to -x: off by 4.37e-08
    0x00000000, // rodrigues 90 deg about z keeps z: off by 5.96e-08
    0x00000000, // rodrigues 90 deg about z keeps z: off by 5.96e-08
    0x3f7fffff, // rodrigues 90 deg about z keeps z: off by 5.96e-08
    0x33800000, // rodrigues 120 deg about (1,1,1): x -> y: off by 2.38e-07
    0x3f800002, // rodrigues 120 deg about (1,1,1): x -> y: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): x -> y: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): y -> z: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): y -> z: off by 2.38e-07
    0x3f800002, // rodrigues 120 deg about (1,1,1): y -> z: off by 2.38e-07
    0x3f800002, // rodrigues 120 deg about (1,1,1): z -> x: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): z -> x: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): z -> x: off by 2.38e-07
    0x00000000, // rodrigues 90 deg about 2x maps y to z: off by 4.37e-08
    0xb33bbd2e, // rodrigues 90 deg about 2x maps y to z: off by 4.37e-08
    0x3f800000, // rodrigues 90 deg about 2x maps y to z: off by 4.37e-08
    0x3f3504f3, // quat 90 deg about z: off by 0
    0x00000000, // quat 90 deg about z: off by 0
    0x00000000, // quat 90 deg about z: off by 0
    0x3f3504f3, // quat 90 deg about z: off by 0
    0x33800000, // quat 90 deg about z rotates x to y: off by 5.96e-08
    0x3f7fffff, // quat 90 deg about z rotates x to y: off by 5.96e-08
    0x00000000, // quat 90 deg about z rotates x to y: off by 5.96e-08
    0x00000000, // log(90 deg about z) = (0, 0, pi/2): off by 0
    0x00000000, // log(90 deg about z) = (0, 0, pi/2): off by 0
    0x3fc90fdb, // log(90 deg about z) = (0, 0, pi/2): off by 0
    0xbf9ac70e, // log(120 deg about (-1,1,-1)): off by 1.19e-07
    0x3f9ac70e, // log(120 deg about (-1,1,-1)): off by 1.19e-07
    0xbf9ac70e, // log(120 deg about (-1,1,-1)): off by 1.19e-07
    0x3f3504f3, // exp(0, 0, pi/2): off by 0
    0x00000000, // exp(0, 0, pi/2): off by 0
    0x00000000, // exp(0, 0, pi/2): off by 0
    0x3f3504f3, // exp(0, 0, pi/2): off by 0
    0x364b5edd, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0xb6a979b7, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0x37079493, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0x3c94f3fa, // log(exp(w)) = w, |w| = 0.06: off by 3.73e-09
    0xbcf8414b, // log(exp(w)) = w, |w| = 0.06: off by 3.73e-09
    0x3d469aa2, // log(exp(w)) = w, |w| = 0.06: off by 3.73e-09
    0x3e9b28d0, // log(exp(w)) = w, |w| = 1: off by 5.96e-08
    0xbf014cae, // log(exp(w)) = w, |w| = 1: off by 5.96e-08
    0x3f4ee116, // log(exp(w)) = w, |w| = 1: off by 5.96e-08
    0x3f41f304, // log(exp(w)) = w, |w| = 2.5: off by 0
    0xbfa19fd8, // log(exp(w)) = w, |w| = 2.5: off by 0
    0x40014cad, // log(exp(w)) = w, |w| = 2.5: off by 0
    0x3f707f42, // log(exp(w)) = w, |w| = 3.1: off by 1.19e-07
    0xbfc86a0d, // log(exp(w)) = w, |w| = 3.1: off by 1.19e-07
    0x402054d6, // log(exp(w)) = w, |w| = 3.1: off by 1.19e-07
    0x3f800000, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x40000001, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x40400001, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x3d4ccccc, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3ca3d709, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3cf5c28d, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3d4cccce, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 3.73e-09
    0x3ca3d70a, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 3.73e-09
    0x3cf5c28d, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 3.73e-09
    0x3fc90fda, // rpy at the pole: theta = pi/2: off by 1.19e-07
    0x00000000, // paper, 1 mrad about x = (0, 0.001, 0): off by 0
    0x3a83126f, // paper, 1 mrad about x = (0, 0.001, 0): off by 0
    0x00000000, // paper, 1 mrad about x = (0, 0.001, 0): off by 0
    0x3fc90fdb, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 0
    0x3a83126f, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 0
    0xbfc90fdb, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 0
    0x3d4ccccd, // exact, pure spin = (0.05, 0, 0): off by 0
    0x00000000, // exact, pure spin = (0.05, 0, 0): off by 0
    0x00000000, // exact, pure spin = (0.05, 0, 0): off by 0
    0x3b03126e, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0xbb449ba4, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0x00000000, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0x3a969fba, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0xbb58224d, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0xbc1985fd, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0x3d10d1ae, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 1.12e-08
    0xbd46c187, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 1.12e-08
    0x3f7f89c6, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 1.12e-08
];

pub const MICROMATH: &[u32] = &[
    0x3efffffd, // sin(pi/6) = 1/2: off by 8.94e-08
    0x3f800000, // sin(pi/2) = 1: off by 0
    0xbf353333, // sin(-pi/4) = -sqrt2/2: off by 0.000706
    0x00000000, // sin(0) = 0: off by 0
    0x3effffff, // cos(pi/3) = 1/2: off by 2.98e-08
    0x3f800000, // cos(0) = 1: off by 0
    0xbf800000, // cos(pi) = -1: off by 0
    0xbf000000, // cos(-2pi/3) = -1/2: off by 0
    0x3efffffd, // sin_cos(pi/6) = (1/2, sqrt3/2): off by 0.000641
    0x3f5ddddd, // sin_cos(pi/6) = (1/2, sqrt3/2): off by 0.000641
    0xbf353333, // sin_cos(-3pi/4): off by 0.000706
    0xbf353333, // sin_cos(-3pi/4): off by 0.000706
    0x3effffc6, // sin(pi/6 + 16 pi) = 1/2: off by 1.73e-06
    0x3f490fdb, // atan2(1, 1) = pi/4: off by 0
    0x4016cbe4, // atan2(1, -1) = 3pi/4: off by 0
    0xc016cbe4, // atan2(-1, -1) = -3pi/4: off by 0
    0xbf490fdb, // atan2(-1, 1) = -pi/4: off by 0
    0x3f85ae16, // atan2(sqrt3, 1) = pi/3: off by 0.00282
    0x3fc90fdb, // atan2(1, 0) = pi/2: off by 0
    0xbfc90fdb, // atan2(-1, 0) = -pi/2: off by 0
    0x00000000, // atan2(0, 1) = 0: off by 0
    0x40490fdb, // atan2(+0, -1) = pi: off by 0
    0x40000000, // sqrt of a known square: off by 0
    0x3f000000, // sqrt of a known square: off by 0
    0x3fc00000, // sqrt of a known square: off by 0.0858
    0x4544aa20, // sqrt of a known square: off by 147
    0x00000000, // rodrigues 90 deg about z maps x to y: off by 0
    0x3f800000, // rodrigues 90 deg about z maps x to y: off by 0
    0x00000000, // rodrigues 90 deg about z maps x to y: off by 0
    0xbf800000, // rodrigues 90 deg about z maps y to -x: off by 0
    0x00000000, // rodrigues 90 deg about z maps y to -x: off by 0
    0x00000000, // rodrigues 90 deg about z maps y to -x: off by 0
    0x00000000, // rodrigues 90 deg about z keeps z: off by 0
    0x00000000, // rodrigues 90 deg about z keeps z: off by 0
    0x3f800000, // rodrigues 90 deg about z keeps z: off by 0
    0x34000000, // rodrigues 120 deg about (1,1,1): x -> y: off by 0.00037
    0x3f800c23, // rodrigues 120 deg about (1,1,1): x -> y: off by 0.00037
    0xb9c21000, // rodrigues 120 deg about (1,1,1): x -> y: off by 0.00037
    0xb9c21000, // rodrigues 120 deg about (1,1,1): y -> z: off by 0.00037
    0x34000000, // rodrigues 120 deg about (1,1,1): y -> z: off by 0.00037
    0x3f800c23, // rodrigues 120 deg about (1,1,1): y -> z: off by 0.00037
    0x3f800c23, // rodrigues 120 deg about (1,1,1): z -> x: off by 0.00037
    0xb9c21000, // rodrigues 120 deg about (1,1,1): z -> x: off by 0.00037
    0x34000000, // rodrigues 120 deg about (1,1,1): z -> x: off by 0.00037
    0x00000000, // rodrigues 90 deg about 2x maps y to z: off by 0
    0x00000000, // rodrigues 90 deg about 2x maps y to z: off by 0
    0x3f800000, // rodrigues 90 deg about 2x maps y to z: off by 0
    0x3f353333, // quat 90 deg about z: off by 0.000706
    0x00000000, // quat 90 deg about z: off by 0.000706
    0x00000000, // quat 90 deg about z: off by 0.000706
    0x3f353333, // quat 90 deg about z: off by 0.000706
    0xbb02e000, // quat 90 deg about z rotates x to y: off by 0.002
    0x3f804170, // quat 90 deg about z rotates x to y: off by 0.002
    0x00000000, // quat 90 deg about z rotates x to y: off by 0.002
    0x00000000, // log(90 deg about z) = (0, 0, pi/2): off by 0.0352
    0x00000000, // log(90 deg about z) = (0, 0, pi/2): off by 0.0352
    0x3fc48da3, // log(90 deg about z) = (0, 0, pi/2): off by 0.0352
    0xbf996d91, // log(120 deg about (-1,1,-1)): off by 0.0105
    0x3f996d91, // log(120 deg about (-1,1,-1)): off by 0.0105
    0xbf996d91, // log(120 deg about (-1,1,-1)): off by 0.0105
    0x3f30f9ff, // exp(0, 0, pi/2): off by 0.0158
    0x00000000, // exp(0, 0, pi/2): off by 0.0158
    0x00000000, // exp(0, 0, pi/2): off by 0.0158
    0x3f340c0c, // exp(0, 0, pi/2): off by 0.0158
    0x364b5edd, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0xb6a979b7, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0x37079493, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0x3c9332fe, // log(exp(w)) = w, |w| = 0.06: off by 0.000571
    0xbcf554fd, // log(exp(w)) = w, |w| = 0.06: off by 0.000571
    0x3d4443fd, // log(exp(w)) = w, |w| = 0.06: off by 0.000571
    0x3e9be4fd, // log(exp(w)) = w, |w| = 1: off by 0.00383
    0xbf01e97d, // log(exp(w)) = w, |w| = 1: off by 0.00383
    0x3f4fdbfc, // log(exp(w)) = w, |w| = 1: off by 0.00383
    0x3f457ea0, // log(exp(w)) = w, |w| = 2.5: off by 0.0369
    0xbfa4942f, // log(exp(w)) = w, |w| = 2.5: off by 0.0369
    0x4003a9c0, // log(exp(w)) = w, |w| = 2.5: off by 0.0369
    0xbf6f1da2, // log(exp(w)) = w, |w| = 3.1: off by 0.0816
    0x3fc7435c, // log(exp(w)) = w, |w| = 3.1: off by 0.0816
    0xc01f6915, // log(exp(w)) = w, |w| = 3.1: off by 0.0816
    0x3f800000, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x40000001, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x40400001, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x3d4ccccc, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3ca3d709, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3cf5c28d, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3d43e5b4, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 0.00217
    0x3c9adba0, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 0.00217
    0x3ce94441, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 0.00217
    0x3fc90fda, // rpy at the pole: theta = pi/2: off by 1.19e-07
    0x00000000, // paper, 1 mrad about x = (0, 0.001, 0): off by 6.27e-05
    0x3a75b2fb, // paper, 1 mrad about x = (0, 0.001, 0): off by 6.27e-05
    0x00000000, // paper, 1 mrad about x = (0, 0.001, 0): off by 6.27e-05
    0x3fc90fdb, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 6.27e-05
    0x3a75b2fb, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 6.27e-05
    0xbfc90fdb, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 6.27e-05
    0x3d4ccccd, // exact, pure spin = (0.05, 0, 0): off by 0
    0x00000000, // exact, pure spin = (0.05, 0, 0): off by 0
    0x00000000, // exact, pure spin = (0.05, 0, 0): off by 0
    0x3b03126e, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0xbb449ba4, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0x00000000, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0x3a969fba, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0xbb58224d, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0xbc1985fd, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0x3d0ed6a4, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 0.000609
    0xbd4442b3, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 0.000609
    0x3f7f8cd2, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 0.000609
];

pub const FAST: &[u32] = &[
    0x3f000000, // sin(pi/6) = 1/2: off by 0
    0x3f800000, // sin(pi/2) = 1: off by 0
    0xbf3504f3, // sin(-pi/4) = -sqrt2/2: off by 0
    0x00000000, // sin(0) = 0: off by 0
    0x3effffff, // cos(pi/3) = 1/2: off by 2.98e-08
    0x3f800000, // cos(0) = 1: off by 0
    0xbf800000, // cos(pi) = -1: off by 0
    0xbf000001, // cos(-2pi/3) = -1/2: off by 5.96e-08
    0x3f000000, // sin_cos(pi/6) = (1/2, sqrt3/2): off by 0
    0x3f5db3d7, // sin_cos(pi/6) = (1/2, sqrt3/2): off by 0
    0xbf3504f3, // sin_cos(-3pi/4): off by 0
    0xbf3504f3, // sin_cos(-3pi/4): off by 0
    0x3f000004, // sin(pi/6 + 16 pi) = 1/2: off by 2.38e-07
    0x3f490fdb, // atan2(1, 1) = pi/4: off by 0
    0x4016cbe4, // atan2(1, -1) = 3pi/4: off by 0
    0xc016cbe4, // atan2(-1, -1) = -3pi/4: off by 0
    0xbf490fdb, // atan2(-1, 1) = -pi/4: off by 0
    0x3f860a92, // atan2(sqrt3, 1) = pi/3: off by 0
    0x3fc90fdb, // atan2(1, 0) = pi/2: off by 0
    0xbfc90fdb, // atan2(-1, 0) = -pi/2: off by 0
    0x00000000, // atan2(0, 1) = 0: off by 0
    0x40490fdb, // atan2(+0, -1) = pi: off by 0
    0x40000000, // sqrt of a known square: off by 0
    0x3f000000, // sqrt of a known square: off by 0
    0x3fb504f3, // sqrt of a known square: off by 0
    0x453b8000, // sqrt of a known square: off by 0
    0xb33bbd30, // rodrigues 90 deg about z maps x to y: off by 4.37e-08
    0x3f800000, // rodrigues 90 deg about z maps x to y: off by 4.37e-08
    0x00000000, // rodrigues 90 deg about z maps x to y: off by 4.37e-08
    0xbf800000, // rodrigues 90 deg about z maps y to -x: off by 4.37e-08
    0xb33bbd30, // rodrigues 90 deg about z maps y to -x: off by 4.37e-08
    0x00000000, // rodrigues 90 deg about z maps y to -x: off by 4.37e-08
    0x00000000, // rodrigues 90 deg about z keeps z: off by 5.96e-08
    0x00000000, // rodrigues 90 deg about z keeps z: off by 5.96e-08
    0x3f7fffff, // rodrigues 90 deg about z keeps z: off by 5.96e-08
    0x33800000, // rodrigues 120 deg about (1,1,1): x -> y: off by 2.38e-07
    0x3f800002, // rodrigues 120 deg about (1,1,1): x -> y: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): x -> y: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): y -> z: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): y -> z: off by 2.38e-07
    0x3f800002, // rodrigues 120 deg about (1,1,1): y -> z: off by 2.38e-07
    0x3f800002, // rodrigues 120 deg about (1,1,1): z -> x: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): z -> x: off by 2.38e-07
    0x33800000, // rodrigues 120 deg about (1,1,1): z -> x: off by 2.38e-07
    0x00000000, // rodrigues 90 deg about 2x maps y to z: off by 4.37e-08
    0xb33bbd30, // rodrigues 90 deg about 2x maps y to z: off by 4.37e-08
    0x3f800000, // rodrigues 90 deg about 2x maps y to z: off by 4.37e-08
    0x3f3504f3, // quat 90 deg about z: off by 0
    0x00000000, // quat 90 deg about z: off by 0
    0x00000000, // quat 90 deg about z: off by 0
    0x3f3504f3, // quat 90 deg about z: off by 0
    0x33800000, // quat 90 deg about z rotates x to y: off by 5.96e-08
    0x3f7fffff, // quat 90 deg about z rotates x to y: off by 5.96e-08
    0x00000000, // quat 90 deg about z rotates x to y: off by 5.96e-08
    0x00000000, // log(90 deg about z) = (0, 0, pi/2): off by 0
    0x00000000, // log(90 deg about z) = (0, 0, pi/2): off by 0
    0x3fc90fdb, // log(90 deg about z) = (0, 0, pi/2): off by 0
    0xbf9ac70e, // log(120 deg about (-1,1,-1)): off by 1.19e-07
    0x3f9ac70e, // log(120 deg about (-1,1,-1)): off by 1.19e-07
    0xbf9ac70e, // log(120 deg about (-1,1,-1)): off by 1.19e-07
    0x3f3504f3, // exp(0, 0, pi/2): off by 0
    0x00000000, // exp(0, 0, pi/2): off by 0
    0x00000000, // exp(0, 0, pi/2): off by 0
    0x3f3504f3, // exp(0, 0, pi/2): off by 0
    0x364b5edd, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0xb6a979b7, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0x37079493, // log(exp(w)) = w, |w| = 1e-5: off by 0
    0x3c94f3fa, // log(exp(w)) = w, |w| = 0.06: off by 3.73e-09
    0xbcf8414b, // log(exp(w)) = w, |w| = 0.06: off by 3.73e-09
    0x3d469aa2, // log(exp(w)) = w, |w| = 0.06: off by 3.73e-09
    0x3e9b28cf, // log(exp(w)) = w, |w| = 1: off by 2.98e-08
    0xbf014cad, // log(exp(w)) = w, |w| = 1: off by 2.98e-08
    0x3f4ee115, // log(exp(w)) = w, |w| = 1: off by 2.98e-08
    0x3f41f304, // log(exp(w)) = w, |w| = 2.5: off by 0
    0xbfa19fd8, // log(exp(w)) = w, |w| = 2.5: off by 0
    0x40014cad, // log(exp(w)) = w, |w| = 2.5: off by 0
    0x3f707f42, // log(exp(w)) = w, |w| = 3.1: off by 1.19e-07
    0xbfc86a0d, // log(exp(w)) = w, |w| = 3.1: off by 1.19e-07
    0x402054d6, // log(exp(w)) = w, |w| = 3.1: off by 1.19e-07
    0x3f800000, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x40000001, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x40400001, // Rot3::from_quat agrees with Rodrigues: off by 2.38e-07
    0x3d4ccccc, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3ca3d709, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3cf5c28d, // exact of the scene increment = rotation vector: off by 3.73e-09
    0x3d4cccce, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 3.73e-09
    0x3ca3d70a, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 3.73e-09
    0x3cf5c28d, // rpy of Rz(0.05) Ry(0.02) Rx(0.03): off by 3.73e-09
    0x3fc90fda, // rpy at the pole: theta = pi/2: off by 1.19e-07
    0x00000000, // paper, 1 mrad about x = (0, 0.001, 0): off by 0
    0x3a83126f, // paper, 1 mrad about x = (0, 0.001, 0): off by 0
    0x00000000, // paper, 1 mrad about x = (0, 0.001, 0): off by 0
    0x3fc90fdb, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 0
    0x3a83126f, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 0
    0xbfc90fdb, // paper, 1 mrad about y = (pi/2, 0.001, -pi/2): off by 0
    0x3d4ccccd, // exact, pure spin = (0.05, 0, 0): off by 0
    0x00000000, // exact, pure spin = (0.05, 0, 0): off by 0
    0x00000000, // exact, pure spin = (0.05, 0, 0): off by 0
    0x3b03126e, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0xbb449ba4, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0x00000000, // plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0): off by 2.33e-10
    0x3a969fba, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0xbb58224d, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0xbc1985fd, // plane, exact: fingertip contact = q_n* (0, 0, -rho): off by 4.66e-10
    0x3d10d1ae, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 1.12e-08
    0xbd46c187, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 1.12e-08
    0x3f7f89c6, // sphere, exact: normal after 10 steps = Rot(n kappa w) z: off by 1.12e-08
];
