//! The scalar the reference is generic over (f32 to match the shader, f64 as
//! the oracle) and a 3-vector over it.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use num_traits::Float;

/// The CPU reference's scalar: `f32` (the shader's precision) or `f64`
/// (the oracle). Sealed: glint implements it for these two alone.
pub trait Real: Float + Debug + Send + Sync + AddAssign + sealed::Sealed + 'static {
    /// Veltkamp's splitting constant, 2^ceil(p/2) + 1 for a p-bit significand.
    const SPLIT: f64;
    /// `v`, rounded to this precision.
    fn of(v: f64) -> Self;
    /// The value, rounded to f32.
    fn to_f32(self) -> f32;
    /// The value in f64, exactly.
    fn to_f64(self) -> f64;
    /// atan2 as the shader takes it: glint's own in f32 (`own_math`), the
    /// exact function in f64.
    fn atan2_shader(self, x: Self) -> Self;
    /// asin as the shader takes it (as `atan2_shader`).
    fn asin_shader(self) -> Self;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

impl Real for f32 {
    const SPLIT: f64 = 4097.0;
    fn of(v: f64) -> Self {
        v as f32
    }
    fn to_f32(self) -> f32 {
        self
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn atan2_shader(self, x: Self) -> Self {
        super::own_math::atan2(self, x)
    }
    fn asin_shader(self) -> Self {
        super::own_math::asin(self)
    }
}

impl Real for f64 {
    const SPLIT: f64 = 134_217_729.0;
    fn of(v: f64) -> Self {
        v
    }
    fn to_f32(self) -> f32 {
        self as f32
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn atan2_shader(self, x: Self) -> Self {
        self.atan2(x)
    }
    fn asin_shader(self) -> Self {
        self.asin()
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vec3<R> {
    pub x: R,
    pub y: R,
    pub z: R,
}

impl<R: Real> Vec3<R> {
    pub fn new(x: R, y: R, z: R) -> Self {
        Self { x, y, z }
    }
    pub fn splat(v: R) -> Self {
        Self::new(v, v, v)
    }
    pub fn zero() -> Self {
        Self::splat(R::zero())
    }
    pub fn of(v: glam::DVec3) -> Self {
        Self::new(R::of(v.x), R::of(v.y), R::of(v.z))
    }
    /// An image's colour (or a texel) in this precision.
    pub fn of_rgb(c: [f32; 3]) -> Self {
        Self::new(
            R::of(f64::from(c[0])),
            R::of(f64::from(c[1])),
            R::of(f64::from(c[2])),
        )
    }
    /// The vector in f64, exactly.
    pub fn to_dvec(self) -> glam::DVec3 {
        glam::DVec3::new(self.x.to_f64(), self.y.to_f64(), self.z.to_f64())
    }
    /// This colour as an image stores it.
    pub fn to_rgb(self) -> [f32; 3] {
        [self.x.to_f32(), self.y.to_f32(), self.z.to_f32()]
    }
    pub fn dot(self, o: Self) -> R {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    pub fn length(self) -> R {
        self.dot(self).sqrt()
    }
    pub fn normalize(self) -> Self {
        self * self.length().recip()
    }
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

impl<R: Real> Add for Vec3<R> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<R: Real> AddAssign for Vec3<R> {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<R: Real> Sub for Vec3<R> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<R: Real> Neg for Vec3<R> {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl<R: Real> Mul<R> for Vec3<R> {
    type Output = Self;
    fn mul(self, s: R) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

/// Per-channel product of two colours.
impl<R: Real> Mul for Vec3<R> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
}

impl<R: Real> Div<R> for Vec3<R> {
    type Output = Self;
    fn div(self, s: R) -> Self {
        Self::new(self.x / s, self.y / s, self.z / s)
    }
}

/// x^n with the scene format's conventions: x^0 = 1 (also for x = 0), and 0 for x <= 0
/// otherwise; GLSL's pow leaves both undefined. x is a cosine, taken at
/// most 1: the rounding of unit vectors can put their dot product an ulp
/// past it, and a large n would raise that past the shading's bound.
pub fn spec_pow<R: Real>(x: R, n: R) -> R {
    if n == R::zero() {
        R::one()
    } else if x <= R::zero() {
        R::zero()
    } else {
        x.min(R::one()).powf(n)
    }
}
