//! A small 3-vector of f32. The frame a vector lives in is stated wherever one is stored.

use crate::math::Math;
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A 3-vector (x, y, z) in f32. Plain data, `Copy`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Vec3 {
    /// x component.
    pub x: f32,
    /// y component.
    pub y: f32,
    /// z component.
    pub z: f32,
}

/// [`Vec3::CUBE_DIRECTIONS`], built at compile time.
const fn cube_directions() -> [Vec3; 26] {
    let mut out = [Vec3::ZERO; 26];
    let (mut k, mut i) = (0, 0);
    while k < 27 {
        if k != 13 {
            let (x, y, z) = (k / 9 - 1, k / 3 % 3 - 1, k % 3 - 1);
            out[i] = Vec3::new(x as f32, y as f32, z as f32);
            i += 1;
        }
        k += 1;
    }
    out
}

impl Vec3 {
    /// The zero vector.
    pub const ZERO: Vec3 = Vec3::new(0.0, 0.0, 0.0);
    /// The 26 directions from a cube's centre to its faces, edges and corners: every (x, y, z) in
    /// {−1, 0, 1}³ but the origin, in lexicographic order (x slowest), not normalised (each
    /// component is exact). The sweep directions of the rolling tests.
    pub const CUBE_DIRECTIONS: [Vec3; 26] = cube_directions();
    /// Unit x axis.
    pub const X: Vec3 = Vec3::new(1.0, 0.0, 0.0);
    /// Unit y axis.
    pub const Y: Vec3 = Vec3::new(0.0, 1.0, 0.0);
    /// Unit z axis (the contact normal in the object frame of a plane).
    pub const Z: Vec3 = Vec3::new(0.0, 0.0, 1.0);

    /// The vector (x, y, z).
    #[inline]
    pub const fn new(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3 { x, y, z }
    }
    /// Dot product `self · o`.
    #[inline]
    pub fn dot(self, o: Vec3) -> f32 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Cross product `self × o` (right-handed).
    #[inline]
    pub fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    /// Squared Euclidean norm `self · self` (no square root).
    #[inline]
    pub fn norm_squared(self) -> f32 {
        self.dot(self)
    }
    /// Euclidean norm with backend `M`'s square root.
    #[inline]
    pub fn norm<M: Math>(self) -> f32 {
        M::sqrt(self.norm_squared())
    }
    /// True when all three components are finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        crate::flags::all_finite(&[self.x, self.y, self.z])
    }
    /// The components as `[x, y, z]`.
    #[inline]
    pub fn to_array(self) -> [f32; 3] {
        [self.x, self.y, self.z]
    }
    /// The vector from `[x, y, z]`.
    #[inline]
    pub const fn from_array(a: [f32; 3]) -> Vec3 {
        Vec3::new(a[0], a[1], a[2])
    }
}

impl Add for Vec3 {
    type Output = Vec3;
    #[inline]
    fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl AddAssign for Vec3 {
    #[inline]
    fn add_assign(&mut self, o: Vec3) {
        *self = *self + o;
    }
}
impl Sub for Vec3 {
    type Output = Vec3;
    #[inline]
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl SubAssign for Vec3 {
    #[inline]
    fn sub_assign(&mut self, o: Vec3) {
        *self = *self - o;
    }
}
impl Mul<f32> for Vec3 {
    type Output = Vec3;
    #[inline]
    fn mul(self, s: f32) -> Vec3 {
        Vec3::new(self.x * s, self.y * s, self.z * s)
    }
}
impl Neg for Vec3 {
    type Output = Vec3;
    #[inline]
    fn neg(self) -> Vec3 {
        Vec3::new(-self.x, -self.y, -self.z)
    }
}

#[cfg(test)]
mod tests {
    use super::Vec3;

    /// The 26 directions are the nested loops over {−1, 0, 1}³ (x slowest) without the origin.
    #[test]
    fn cube_directions_are_the_lattice_neighbours_in_order() {
        let mut expected = std::vec::Vec::new();
        for x in -1..=1 {
            for y in -1..=1 {
                for z in -1..=1 {
                    if (x, y, z) != (0, 0, 0) {
                        expected.push(Vec3::new(x as f32, y as f32, z as f32));
                    }
                }
            }
        }
        assert_eq!(Vec3::CUBE_DIRECTIONS.to_vec(), expected);
    }
}
