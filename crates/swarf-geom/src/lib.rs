//! Geometry kernel of swarf: vectors, frames, rigid motions and implicit primitives.
//!
//! # Model
//! Everything is `f64` ([`math::Real`]) and every length is in **millimetres**; angles at the
//! public interfaces of swarf are in degrees, but inside this crate they are radians (the
//! conversion happens where numbers enter or leave swarf). The vector type is glam's `DVec3`,
//! aliased once in [`math`] so the whole workspace (and parry3d-f64, which uses the same type)
//! agrees on it.
//!
//! Frames are right-handed and orthonormal. A [`Frame`] places a local coordinate system in the
//! world; a [`RigidMotion`] moves points and vectors. The implicit primitives (plane, sphere,
//! cylinder, cone, torus) answer the two queries every later stage needs: where a ray crosses
//! them ([`Implicit::ray_intersections`]) and how far a point is from them
//! ([`Implicit::signed_distance`], negative inside).
//!
//! Long computations everywhere in swarf report progress and may be stopped through one
//! [`Observer`] type ([`progress`]).
//!
//! ```
//! use swarf_geom::math::Vec3;
//! use swarf_geom::{Frame, Implicit, Ray, Sphere};
//! let s = Sphere::new(Vec3::ZERO, 2.0);
//! let mut hits = Vec::new();
//! s.ray_intersections(&Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X), &mut hits);
//! assert_eq!(hits.len(), 2);
//! assert!((hits[0] - 3.0).abs() < 1e-12 && (hits[1] - 7.0).abs() < 1e-12);
//! assert!((s.signed_distance(Vec3::ZERO) + 2.0).abs() < 1e-12);
//! let f = Frame::from_axis(Vec3::ZERO, Vec3::Z);
//! assert!((f.z - Vec3::Z).length() < 1e-12);
//! ```

pub mod aabb;
pub mod frame;
pub mod math;
pub mod motion;
pub mod poly;
pub mod primitive;
pub mod progress;
pub mod ray;
pub mod search;
pub mod text;

pub use aabb::Aabb;
pub use frame::Frame;
pub use motion::RigidMotion;
pub use poly::RootTolerance;
pub use primitive::{Cone, Cylinder, Implicit, Plane, Sphere, Torus};
pub use progress::{Cancelled, Observer, Quiet};
pub use ray::Ray;
