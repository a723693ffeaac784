//! Multiple importance sampling over the connection strategies (Veach 1997, section
//! 10.2; pbrt-v4 `MISWeight`). A path of `n = s + t` vertices could have been sampled by
//! every split `(s', t')` with `s' + t' = n`; the weight of strategy `(s, t)` is
//! `p_s^2 / sum_i p_i^2` (the power heuristic), computed from the ratios
//! `p_{i+1} / p_i = pdf_rev / pdf_fwd` of the densities each vertex was (or could have been)
//! sampled with from either side.
//!
//! The connection changes the reverse densities of the two connected vertices and of their
//! predecessors, so those four are re-evaluated here. Specular vertices have both densities
//! zero (remapped to one so the ratios pass through them) and no strategy may connect at
//! them; a light endpoint of a delta light cannot be hit, so the strategy that would hit
//! it is left out.

use super::vertex::{Context, Vertex};

/// Which MIS weighting to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MisMode {
    /// The power heuristic over all strategies.
    Power,
    /// No weighting: every strategy's contribution counts in full (for studying the
    /// strategies one by one; their sum overcounts).
    Off,
}

/// The MIS weight of connecting the first `s` light vertices with the first `t` camera
/// vertices. `sampled` replaces the last light vertex when `s == 1` (a light sample) or
/// the last camera vertex when `t == 1` (a camera sample).
#[must_use]
pub fn mis_weight(
    ctx: &Context<'_>,
    light: &[Vertex],
    camera: &[Vertex],
    sampled: Option<&Vertex>,
    s: usize,
    t: usize,
) -> f32 {
    if s + t == 2 {
        return 1.0;
    }
    let remap0 = |f: f32| if f == 0.0 { 1.0 } else { f };
    let sq = |f: f32| f * f;

    // The connection vertices and their predecessors, the sampled vertex in place.
    let qs: Option<&Vertex> = match s {
        0 => None,
        1 => Some(sampled.unwrap_or(&light[0])),
        _ => Some(&light[s - 1]),
    };
    let pt: Option<&Vertex> = match t {
        0 => None,
        1 => Some(sampled.unwrap_or(&camera[0])),
        _ => Some(&camera[t - 1]),
    };
    let qs_minus = if s > 1 { Some(&light[s - 2]) } else { None };
    let pt_minus = if t > 1 { Some(&camera[t - 2]) } else { None };

    // Reverse densities of the vertices around the connection.
    let pt_rev = pt.map(|pt| match qs {
        Some(qs) => qs.pdf(ctx, qs_minus, pt),
        None => pt.pdf_light_origin(ctx, pt_minus.expect("s = 0 needs t >= 2")),
    });
    let pt_minus_rev = pt_minus.map(|ptm| {
        let pt = pt.expect("pt exists when pt_minus does");
        match qs {
            Some(qs) => pt.pdf(ctx, Some(qs), ptm),
            None => pt.pdf_light(ctx, ptm),
        }
    });
    let qs_rev = qs.map(|qs| pt.expect("t >= 1").pdf(ctx, pt_minus, qs));
    let qs_minus_rev = qs_minus.map(|qsm| qs.expect("qs exists").pdf(ctx, pt, qsm));

    // The camera vertex `i` with the connection's changes applied.
    let cam = |i: usize| -> (f32, f32, bool) {
        let v = if i + 1 == t { pt.expect("t >= 1") } else { &camera[i] };
        let rev = if i + 1 == t {
            pt_rev.unwrap_or(v.pdf_rev)
        } else if i + 2 == t {
            pt_minus_rev.unwrap_or(v.pdf_rev)
        } else {
            v.pdf_rev
        };
        (v.pdf_fwd, rev, v.delta && i + 1 != t)
    };
    let lig = |i: usize| -> (f32, f32, bool) {
        let v = if i + 1 == s { qs.expect("s >= 1") } else { &light[i] };
        let rev = if i + 1 == s {
            qs_rev.unwrap_or(v.pdf_rev)
        } else if i + 2 == s {
            qs_minus_rev.unwrap_or(v.pdf_rev)
        } else {
            v.pdf_rev
        };
        (v.pdf_fwd, rev, v.delta && i + 1 != s)
    };

    let mut sum_ri = 0.0f32;
    // Strategies with fewer camera vertices.
    let mut ri = 1.0f32;
    for i in (1..t).rev() {
        let (fwd, rev, delta) = cam(i);
        ri *= sq(remap0(rev) / remap0(fwd));
        if !delta && !cam(i - 1).2 {
            sum_ri += ri;
        }
    }
    // Strategies with fewer light vertices.
    let mut ri = 1.0f32;
    for i in (0..s).rev() {
        let (fwd, rev, delta) = lig(i);
        ri *= sq(remap0(rev) / remap0(fwd));
        let delta_before = if i > 0 {
            lig(i - 1).2
        } else {
            qs.filter(|_| s == 1).unwrap_or(&light[0]).is_delta_light(ctx.scene)
        };
        if !delta && !delta_before {
            sum_ri += ri;
        }
    }
    1.0 / (1.0 + sum_ri)
}
