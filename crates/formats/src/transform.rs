//! The matrices of pbrt-v4's transform directives (`Translate`, `Scale`, `Rotate`,
//! `LookAt`, `Transform`/`ConcatTransform`), as `glam::Mat4` in pbrt's convention: column
//! vectors, `p' = M p`, and each directive post-multiplies the current transform
//! (`CTM = CTM * T`).

use glam::{Mat4, Vec3, Vec4};

/// `Translate dx dy dz`.
#[must_use]
pub fn translate(d: Vec3) -> Mat4 {
    Mat4::from_translation(d)
}

/// `Scale sx sy sz`.
#[must_use]
pub fn scale(s: Vec3) -> Mat4 {
    Mat4::from_scale(s)
}

/// `Rotate angle x y z`: `angle` degrees counter-clockwise (right-hand rule) about the axis.
/// `None` when the axis has zero length.
#[must_use]
pub fn rotate(angle_degrees: f32, axis: Vec3) -> Option<Mat4> {
    let axis = axis.try_normalize()?;
    Some(Mat4::from_axis_angle(axis, angle_degrees.to_radians()))
}

/// `LookAt eye look up`: pbrt's camera-from-world matrix for a camera at `eye` looking at
/// `look`, with camera +z the viewing direction, +y up and +x to the right (left-handed).
///
/// # Errors
/// A message when `eye == look` or `up` is parallel to the viewing direction.
pub fn look_at(eye: Vec3, look: Vec3, up: Vec3) -> Result<Mat4, String> {
    let dir = (look - eye)
        .try_normalize()
        .ok_or_else(|| "LookAt: the eye point and the look-at point are the same".to_string())?;
    let right = up
        .try_normalize()
        .and_then(|up| up.cross(dir).try_normalize())
        .ok_or_else(|| {
            format!(
                "LookAt: the \"up\" vector ({} {} {}) is zero or parallel to the viewing direction",
                up.x, up.y, up.z
            )
        })?;
    let new_up = dir.cross(right);
    let world_from_camera = Mat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        Vec4::new(eye.x, eye.y, eye.z, 1.0),
    );
    let camera_from_world = world_from_camera.inverse();
    if camera_from_world.is_finite() {
        Ok(camera_from_world)
    } else {
        Err("LookAt: the viewing transformation is singular".to_string())
    }
}

/// `Transform [16 numbers]` / `ConcatTransform [...]`: pbrt reads the numbers row by row and
/// transposes, so they are the matrix's columns one after another.
#[must_use]
pub fn from_pbrt_array(values: &[f32; 16]) -> Mat4 {
    Mat4::from_cols_array(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    #[test]
    fn translate_and_scale_match_hand_computed_matrices() {
        let t = translate(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(t.col(3), Vec4::new(1.0, 2.0, 3.0, 1.0));
        assert_eq!(t.transform_point3(Vec3::ZERO), Vec3::new(1.0, 2.0, 3.0));
        let s = scale(Vec3::new(2.0, -1.0, 0.5));
        assert_eq!(
            s,
            Mat4::from_cols_array(&[2., 0., 0., 0., 0., -1., 0., 0., 0., 0., 0.5, 0., 0., 0., 0., 1.])
        );
    }

    #[test]
    fn rotate_is_counter_clockwise_about_the_axis() {
        let r = rotate(90.0, Vec3::new(0.0, 0.0, 2.0)).unwrap();
        assert!(close(r.transform_vector3(Vec3::X), Vec3::Y));
        assert!(close(r.transform_vector3(Vec3::Y), -Vec3::X));
        let r = rotate(90.0, Vec3::X).unwrap();
        assert!(close(r.transform_vector3(Vec3::Y), Vec3::Z));
        let r = rotate(90.0, Vec3::Y).unwrap();
        assert!(close(r.transform_vector3(Vec3::Z), Vec3::X));
        // pbrt's matrix for a general axis: m[0][1] = ax ay (1 - c) - az s, and so on.
        let a = Vec3::new(1.0, 2.0, 3.0).normalize();
        let (s, c) = 30f32.to_radians().sin_cos();
        let r = rotate(30.0, Vec3::new(1.0, 2.0, 3.0)).unwrap();
        let row0 = Vec3::new(
            a.x * a.x + (1.0 - a.x * a.x) * c,
            a.x * a.y * (1.0 - c) - a.z * s,
            a.x * a.z * (1.0 - c) + a.y * s,
        );
        assert!(close(r.row(0).truncate(), row0));
        assert!(rotate(10.0, Vec3::ZERO).is_none());
    }

    #[test]
    fn look_at_matches_pbrt() {
        // Camera at (0, 1, 6.8) looking down -z: pbrt's matrix maps the eye to the origin and
        // the viewing direction to +z; up stays +y, so +x maps to -x (left-handed camera).
        let m = look_at(Vec3::new(0.0, 1.0, 6.8), Vec3::new(0.0, 1.0, 0.0), Vec3::Y).unwrap();
        let expected = Mat4::from_cols_array(&[-1., 0., 0., 0., 0., 1., 0., 0., 0., 0., -1., 0., 0., -1., 6.8, 1.]);
        assert!(m.abs_diff_eq(expected, 1e-6), "{m:?}");
        // A general case against hand-computed vectors.
        let eye = Vec3::new(1.0, 2.0, 3.0);
        let m = look_at(eye, Vec3::new(4.0, 2.0, 3.0), Vec3::new(0.0, 0.0, 1.0)).unwrap();
        assert!(close(m.transform_point3(eye), Vec3::ZERO));
        assert!(close(m.transform_vector3(Vec3::X), Vec3::Z)); // viewing direction
        assert!(close(m.transform_vector3(Vec3::Z), Vec3::Y)); // up
        assert!(close(m.transform_vector3(Vec3::Y), Vec3::X)); // right = up x dir = z x x = y
        assert!(look_at(eye, eye, Vec3::Y).is_err());
        assert!(look_at(eye, Vec3::new(1.0, 5.0, 3.0), Vec3::Y).is_err());
    }

    #[test]
    fn pbrt_arrays_are_columns() {
        let v: [f32; 16] = [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., -1., 0., 0., -1., 6.8, 1.];
        let m = from_pbrt_array(&v);
        assert_eq!(m.transform_point3(Vec3::new(0.0, 1.0, 6.8)), Vec3::ZERO);
    }
}
