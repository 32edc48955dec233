//! Cameras framed automatically around a bounding box.
//!
//! Views follow asperity's z-up convention: `Iso` looks down at 35.26° from the
//! (+1, −1, +1) diagonal (the classic isometric direction), `Top` looks straight
//! down −z with +y up on screen, `Front` looks along +y with +z up, `Side` along
//! −x. Framing puts the whole bounding sphere in view with a small margin, so
//! any object is visible whatever its size or position.

use asperity_core::Aabb;
use glam::{Mat4, Vec3};

/// Where the camera looks from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum View {
    /// From the (+1, −1, +1) diagonal, looking at the centre.
    Iso,
    /// From +z looking down; +x right, +y up on screen.
    Top,
    /// From −y looking along +y; +x right, +z up.
    Front,
    /// From +x looking along −x; +y right, +z up.
    Side,
    /// Explicit eye and target (world units).
    Explicit {
        /// Camera position.
        eye: [f64; 3],
        /// Point looked at.
        target: [f64; 3],
    },
}

/// Perspective or orthographic projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Perspective with a vertical field of view in degrees.
    Perspective {
        /// Vertical field of view, degrees.
        fov_deg: f64,
    },
    /// Parallel projection (heights and slopes keep their proportions).
    Orthographic,
}

/// A camera: view and projection matrices plus the eye position.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    /// World → view.
    pub view: Mat4,
    /// View → clip.
    pub proj: Mat4,
    /// Eye position (for orthographic: a point far back along the view direction).
    pub eye: Vec3,
    /// Unit viewing direction.
    pub forward: Vec3,
    /// True for orthographic projection.
    pub orthographic: bool,
}

impl Camera {
    /// World → clip.
    pub fn view_proj(&self) -> Mat4 {
        self.proj * self.view
    }

    /// A camera that frames `bounds` from `view` for an image of `aspect` = width/height.
    pub fn frame(bounds: &Aabb, view: View, projection: Projection, aspect: f64) -> Camera {
        Self::frame_points(bounds, None, view, projection, aspect)
    }

    /// Like [`Camera::frame`], but fits the silhouette of `points` (world
    /// positions inside `bounds`) instead of the box's corners, so round objects
    /// fill the frame as well as boxy ones.
    pub fn frame_points(
        bounds: &Aabb,
        points: Option<&[Vec3]>,
        view: View,
        projection: Projection,
        aspect: f64,
    ) -> Camera {
        let c = bounds.center();
        let center = Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
        let radius = (0.5 * bounds.diagonal()).max(1e-9) as f32;
        let (dir, up) = match view {
            View::Iso => (Vec3::new(1.0, -1.0, 1.0).normalize(), Vec3::Z),
            View::Top => (Vec3::Z, Vec3::Y),
            View::Front => (Vec3::NEG_Y, Vec3::Z),
            View::Side => (Vec3::X, Vec3::Z),
            View::Explicit { eye, target } => {
                return Self::explicit(eye, target, center, radius, projection, aspect);
            }
        };
        // Fit the eight box corners, not the bounding sphere: flat height fields
        // would otherwise fill a fraction of the frame.
        let box_corners: Vec<Vec3>;
        let corners: &[Vec3] = match points {
            Some(p) if !p.is_empty() => p,
            _ => {
                box_corners = corners_of(bounds);
                &box_corners
            }
        };
        let fit = Fit {
            center,
            radius,
            back: dir,
            up,
            aspect,
        };
        match projection {
            Projection::Perspective { fov_deg } => fit.perspective(corners, fov_deg, projection),
            Projection::Orthographic => fit.orthographic(corners, projection),
        }
    }

    /// A camera at `eye` looking at `target` (z up unless looking along z).
    fn explicit(
        eye: [f64; 3],
        target: [f64; 3],
        center: Vec3,
        radius: f32,
        projection: Projection,
        aspect: f64,
    ) -> Camera {
        let e = Vec3::new(eye[0] as f32, eye[1] as f32, eye[2] as f32);
        let t = Vec3::new(target[0] as f32, target[1] as f32, target[2] as f32);
        let d = (e - t).normalize_or(Vec3::Z);
        let up = if d.cross(Vec3::Z).length() < 1e-4 {
            Vec3::Y
        } else {
            Vec3::Z
        };
        Self::look(
            e,
            t,
            up,
            projection,
            aspect,
            (radius, (e - center).length()),
        )
    }

    fn look(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        projection: Projection,
        aspect: f64,
        (radius, dist): (f32, f32),
    ) -> Camera {
        let view = Mat4::look_at_rh(eye, target, up);
        let aspect = aspect as f32;
        let near = (dist - 1.5 * radius).max(dist * 1e-3).max(1e-6);
        let far = dist + 1.5 * radius;
        let (proj, orthographic) = match projection {
            Projection::Perspective { fov_deg } => (
                Mat4::perspective_rh_gl((fov_deg as f32).to_radians(), aspect, near, far),
                false,
            ),
            Projection::Orthographic => {
                let h = radius * 1.08;
                let (w, hh) = if aspect >= 1.0 {
                    (h * aspect, h)
                } else {
                    (h, h / aspect)
                };
                (Mat4::orthographic_rh_gl(-w, w, -hh, hh, near, far), true)
            }
        };
        Camera {
            view,
            proj,
            eye,
            forward: (target - eye).normalize(),
            orthographic,
        }
    }
}

/// The eight corners of `bounds`.
fn corners_of(bounds: &Aabb) -> Vec<Vec3> {
    (0..8)
        .map(|k| {
            let pick = |bit: usize, a: usize| {
                if k >> bit & 1 == 1 {
                    bounds.max[a]
                } else {
                    bounds.min[a]
                }
            } as f32;
            Vec3::new(pick(0, 0), pick(1, 1), pick(2, 2))
        })
        .collect()
}

/// Framing points from direction `back` (towards the camera) with `up`.
struct Fit {
    center: Vec3,
    radius: f32,
    back: Vec3,
    up: Vec3,
    aspect: f64,
}

/// Margin around the fitted points.
const MARGIN: f32 = 1.06;

impl Fit {
    /// The camera's right and up axes.
    fn axes(&self) -> (Vec3, Vec3) {
        let right = self.up.cross(self.back).normalize();
        (right, self.back.cross(right))
    }

    /// The nearest perspective camera that sees every corner.
    fn perspective(&self, corners: &[Vec3], fov_deg: f64, projection: Projection) -> Camera {
        let (right, cam_up) = self.axes();
        let ty = ((fov_deg as f32).to_radians() * 0.5).tan();
        let tx = ty * self.aspect as f32;
        let dist = corners
            .iter()
            .map(|c| {
                c.dot(self.back) + (c.dot(right).abs() / tx).max(c.dot(cam_up).abs() / ty) * MARGIN
            })
            .fold(self.radius * 0.1, f32::max);
        Camera::look(
            self.center + self.back * dist,
            self.center,
            self.up,
            projection,
            self.aspect,
            (self.radius, dist),
        )
    }

    /// The smallest orthographic view that holds every corner.
    fn orthographic(&self, corners: &[Vec3], projection: Projection) -> Camera {
        let (right, cam_up) = self.axes();
        let (aspect32, radius) = (self.aspect as f32, self.radius);
        let half = corners
            .iter()
            .map(|&p| {
                let c = p - self.center;
                (c.dot(right).abs() / aspect32).max(c.dot(cam_up).abs())
            })
            .fold(radius * 1e-3, f32::max)
            * MARGIN;
        let dist = 3.0 * radius;
        let mut cam = Camera::look(
            self.center + self.back * dist,
            self.center,
            self.up,
            projection,
            self.aspect,
            (radius, dist),
        );
        cam.proj = Mat4::orthographic_rh_gl(
            -half * aspect32,
            half * aspect32,
            -half,
            half,
            dist - 2.0 * radius,
            dist + 2.0 * radius,
        );
        cam
    }
}
