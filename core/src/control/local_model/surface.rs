//! [`ModelSurface`]: a surface whose kind is chosen at run time, for models received over the
//! link. Each method forwards to the kind's own [`Surface`] implementation.

use crate::contact::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
use crate::control::local_model::spec::ModelKind;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// A plane, sphere, bowl or cylinder, in the model's object frame.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ModelSurface {
    /// The plane z = 0.
    Plane(Plane),
    /// A sphere centred at the origin.
    Sphere(Sphere),
    /// The inside of a sphere centred at the origin.
    Bowl(Bowl),
    /// A cylinder along the x axis.
    Cylinder(Cylinder),
}

impl ModelSurface {
    /// The surface of a model kind, contact point at its start (plane origin, sphere top, bowl
    /// bottom, cylinder top).
    pub fn of(kind: ModelKind) -> ModelSurface {
        match kind {
            ModelKind::Plane => ModelSurface::Plane(Plane::default()),
            ModelKind::Sphere { radius_m } => ModelSurface::Sphere(Sphere::new(radius_m)),
            ModelKind::Bowl { radius_m } => ModelSurface::Bowl(Bowl::new(radius_m)),
            ModelKind::Cylinder { radius_m } => ModelSurface::Cylinder(Cylinder::new(radius_m)),
        }
    }
}

macro_rules! forward {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            ModelSurface::Plane($s) => $e,
            ModelSurface::Sphere($s) => $e,
            ModelSurface::Bowl($s) => $e,
            ModelSurface::Cylinder($s) => $e,
        }
    };
}

impl Surface for ModelSurface {
    #[inline]
    fn curvature(&self) -> f32 {
        forward!(self, s => s.curvature())
    }
    #[inline]
    fn to_contact(&self, v: Vec3) -> Vec3 {
        forward!(self, s => s.to_contact(v))
    }
    #[inline]
    fn to_step_contact<M: Math>(&self, v: Vec3) -> Vec3 {
        forward!(self, s => s.to_step_contact::<M>(v))
    }
    #[inline]
    fn contact_to_object(&self, v: Vec3) -> Vec3 {
        forward!(self, s => s.contact_to_object(v))
    }
    #[inline]
    fn roll<M: Math>(&mut self, w: Vec3, r: f32) -> Vec3 {
        forward!(self, s => s.roll::<M>(w, r))
    }
    #[inline]
    fn contact_point(&self) -> Vec3 {
        forward!(self, s => s.contact_point())
    }
    #[inline]
    fn normal(&self) -> Vec3 {
        forward!(self, s => s.normal())
    }
    #[inline]
    fn place_under<M: Math>(&mut self, c: Vec3) {
        forward!(self, s => s.place_under::<M>(c))
    }
    #[inline]
    fn penetration<M: Math>(&self, c: Vec3, r: f32) -> f32 {
        forward!(self, s => s.penetration::<M>(c, r))
    }
    #[inline]
    fn split(&self, v: Vec3) -> (f32, Vec3) {
        forward!(self, s => s.split(v))
    }
    #[inline]
    fn along_normal(&self, x: f32) -> Vec3 {
        forward!(self, s => s.along_normal(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Libm;

    /// Each kind answers exactly as its own type does.
    #[test]
    fn forwards_to_the_kind() {
        let c = Vec3::new(0.01, -0.02, 0.055);
        let mut m = ModelSurface::of(ModelKind::Sphere { radius_m: 0.05 });
        let mut s = Sphere::new(0.05);
        m.place_under::<Libm>(c);
        s.place_under::<Libm>(c);
        assert_eq!(m.normal(), s.normal());
        assert_eq!(
            m.penetration::<Libm>(c, 0.01),
            s.penetration::<Libm>(c, 0.01)
        );
        let w = Vec3::new(0.001, 0.002, 0.0);
        assert_eq!(m.roll::<Libm>(w, 0.01), s.roll::<Libm>(w, 0.01));
        assert_eq!(m.curvature(), 20.0);
        let mut mb = ModelSurface::of(ModelKind::Bowl { radius_m: 0.05 });
        let mut bo = Bowl::new(0.05);
        mb.place_under::<Libm>(c);
        bo.place_under::<Libm>(c);
        assert_eq!(mb.normal(), bo.normal());
        assert_eq!(
            mb.penetration::<Libm>(c, 0.01),
            bo.penetration::<Libm>(c, 0.01)
        );
        assert_eq!(mb.curvature(), bo.curvature());
        let mut mc = ModelSurface::of(ModelKind::Cylinder { radius_m: 0.05 });
        let mut cy = Cylinder::new(0.05);
        mc.place_under::<Libm>(c);
        cy.place_under::<Libm>(c);
        assert_eq!(mc.normal(), cy.normal());
        assert_eq!(
            mc.penetration::<Libm>(c, 0.01),
            cy.penetration::<Libm>(c, 0.01)
        );
        assert_eq!(mc.roll::<Libm>(w, 0.01), cy.roll::<Libm>(w, 0.01));
        let p = ModelSurface::of(ModelKind::Plane);
        assert_eq!(p.penetration::<Libm>(c, 0.01), 0.01 - 0.055);
        assert_eq!(p.split(c), Plane::default().split(c));
    }
}
