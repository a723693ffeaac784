//! Whether two renders of the same scene (by two loaders, say) agree within their noise.

use mcrender_core::color::Rgb;

/// A render's per-pixel means and variances of the mean.
pub type MeanAndVariance = (Vec<Rgb>, Vec<Rgb>);

/// How two renders compare.
#[derive(Clone, Copy, Debug)]
pub struct Agreement {
    /// Fraction of pixel channels within 3.29 standard errors (two-sided p = 0.001).
    pub within: f64,
    /// The largest z of the per-channel image means.
    pub max_mean_z: f64,
    /// The mean over pixels and channels of the first render (scaled).
    pub mean_a: f64,
}

/// Compare render `a`, scaled by `scale_a`, with render `b`.
pub fn agreement(a: &MeanAndVariance, b: &MeanAndVariance, scale_a: f32) -> Agreement {
    let mut within = 0usize;
    // Per channel: sum of a, sum of b, sum of a's variances, sum of b's.
    let mut sums = [[0.0f64; 4]; 3];
    for i in 0..a.0.len() {
        let (ma, va, mb, vb) = (
            a.0[i].to_array(),
            a.1[i].to_array(),
            b.0[i].to_array(),
            b.1[i].to_array(),
        );
        for k in 0..3 {
            let (x, y) = (f64::from(ma[k] * scale_a), f64::from(mb[k]));
            let (vx, vy) = (f64::from(va[k] * scale_a * scale_a), f64::from(vb[k]));
            let z = (x - y).abs() / (vx + vy).max(1e-12).sqrt();
            within += usize::from(z < 3.29);
            for (s, v) in sums[k].iter_mut().zip([x, y, vx, vy]) {
                *s += v;
            }
        }
    }
    let channels = (3 * a.0.len()) as f64;
    Agreement {
        within: within as f64 / channels,
        max_mean_z: sums
            .iter()
            .map(|s| (s[0] - s[1]).abs() / (s[2] + s[3]).sqrt())
            .fold(0.0, f64::max),
        mean_a: sums.iter().map(|s| s[0]).sum::<f64>() / channels,
    }
}
