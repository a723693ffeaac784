//! The render session's guarantees: a render continued in waves is bit-identical to one
//! pass, whatever the thread count or tile size; cancellation drops the unfinished wave and
//! leaves a film that continues to the same bytes; observers see every tile and the work.

mod common;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::film::{Film, PixelStats};
use mcrender_core::math::Vec2;
use mcrender_core::render::{RenderError, RenderObserver, RenderOptions, RenderSession, Tile};
use mcrender_core::scene::{FilterDesc, IntegratorKind, Scene, SceneDescription};

/// A small noisy scene: a glowing sphere around a diffuse square, three bounces, a
/// Gaussian filter (weights other than one, so rounding shows), a size that does not divide
/// into tiles.
fn scene() -> SceneDescription {
    let mut d = emissive_sphere(5.0, Rgb::splat(0.5), Rgb::new(1.0, 0.7, 0.3));
    add_receiver(&mut d, 0.8);
    d.film.width = 13;
    d.film.height = 9;
    d.filter = FilterDesc::Gaussian {
        radius: Vec2::splat(1.5),
        sigma: 0.5,
    };
    d.integrator.max_depth = 3;
    d.sampler.samples_per_pixel = 7;
    d
}

fn opts(threads: usize, tile_size: u32) -> RenderOptions {
    RenderOptions {
        threads: Some(threads),
        tile_size,
    }
}

fn bits(f: &Film) -> Vec<u64> {
    let mut v: Vec<u64> = f
        .pixels()
        .iter()
        .flat_map(|p| {
            [
                p.sum_w,
                p.sum_wl[0],
                p.sum_wl[1],
                p.sum_wl[2],
                p.sum_wl2[0],
                p.sum_wl2[1],
                p.sum_wl2[2],
            ]
            .map(f64::to_bits)
            .into_iter()
            .chain([p.count])
        })
        .collect();
    v.extend(
        f.splat_sums()
            .iter()
            .flat_map(|s| s.to_fixed())
            .flat_map(|x| [x as u64, (x >> 64) as u64]),
    );
    v.push(f.samples_per_pixel());
    v
}

fn one_pass(scene: &Scene, o: &RenderOptions) -> Film {
    let mut s = RenderSession::new(scene, o).unwrap();
    s.advance(0..7, &()).unwrap();
    s.into_film()
}

#[test]
fn waves_are_bit_identical_to_one_pass() {
    let scene = Scene::build(&scene()).unwrap();
    let whole = one_pass(&scene, &opts(2, 16));
    let mut s = RenderSession::new(&scene, &opts(2, 16)).unwrap();
    for r in [0..1, 1..3, 3..3, 3..7] {
        s.advance(r, &()).unwrap();
    }
    assert_eq!(bits(s.film()), bits(&whole));
    // Merging separately rendered films is only equal up to rounding: the session is needed.
    let mut merged = mcrender_core::render::render_samples(&scene, &opts(2, 16), 0..3, &|_, _| {})
        .unwrap()
        .film;
    merged.merge(
        &mcrender_core::render::render_samples(&scene, &opts(2, 16), 3..7, &|_, _| {})
            .unwrap()
            .film,
    );
    assert_ne!(
        bits(&merged),
        bits(&whole),
        "the scene should be noisy enough to show rounding"
    );
    for (a, b) in merged.mean_image().iter().zip(whole.mean_image()) {
        assert!((*a - b).max_component().abs() < 1e-5);
    }
}

#[test]
fn threads_and_tile_size_do_not_change_the_bytes() {
    let scene = Scene::build(&scene()).unwrap();
    let reference = bits(&one_pass(&scene, &opts(1, 16)));
    for (t, ts) in [(2, 16), (2, 3), (1, 5)] {
        assert_eq!(
            bits(&one_pass(&scene, &opts(t, ts))),
            reference,
            "{t} threads, tiles of {ts}"
        );
    }
}

#[test]
fn ranges_must_continue_the_film() {
    let scene = Scene::build(&scene()).unwrap();
    let mut s = RenderSession::new(&scene, &opts(1, 16)).unwrap();
    s.advance(0..2, &()).unwrap();
    match s.advance(3..5, &()) {
        Err(RenderError::SampleRange { next: 2, .. }) => {}
        other => panic!("expected a sample-range error, got {other:?}"),
    }
    // A driver that fills the film itself records its ranges the same way.
    assert!(s.mark_rendered(5..6).is_err());
    s.mark_rendered(2..4).unwrap();
    assert_eq!((s.next_sample(), s.film().samples_per_pixel()), (Some(4), 4));
    let wrong = Film::new(4, 4);
    assert!(matches!(
        RenderSession::with_film(&scene, &opts(1, 16), wrong, 0),
        Err(RenderError::FilmSize { .. })
    ));
}

/// Sets the cancel flag once `after` tiles have finished; records tiles and progress.
struct CancelAfter {
    after: u64,
    tiles: AtomicU64,
    flag: AtomicBool,
    last_progress: Mutex<(u64, u64)>,
}

impl RenderObserver for CancelAfter {
    fn progress(&self, done: u64, total: u64) {
        let mut p = self.last_progress.lock().unwrap();
        *p = (*p).max((done, total));
    }
    fn tile_finished(&self, _tile: &Tile, _pixels: &[PixelStats]) {
        if self.tiles.fetch_add(1, Ordering::SeqCst) + 1 >= self.after {
            self.flag.store(true, Ordering::SeqCst);
        }
    }
    fn cancel_flag(&self) -> Option<&AtomicBool> {
        Some(&self.flag)
    }
}

fn cancel_after(after: u64) -> CancelAfter {
    CancelAfter {
        after,
        tiles: AtomicU64::new(0),
        flag: AtomicBool::new(false),
        last_progress: Mutex::new((0, 0)),
    }
}

#[test]
fn a_cancelled_wave_is_dropped_and_the_render_continues_identically() {
    let scene = Scene::build(&scene()).unwrap();
    let o = opts(1, 4); // 12 tiles, one thread: the cancel lands between tiles.
    let whole = bits(&one_pass(&scene, &o));
    let mut s = RenderSession::new(&scene, &o).unwrap();
    s.advance(0..2, &()).unwrap();
    let before = bits(s.film());
    let obs = cancel_after(3);
    match s.advance(2..7, &obs) {
        Err(RenderError::Cancelled { samples_done: 2 }) => {}
        other => panic!("expected a cancellation, got {other:?}"),
    }
    assert_eq!(obs.tiles.load(Ordering::SeqCst), 3, "stops at the next work unit");
    assert_eq!(bits(s.film()), before, "the unfinished wave leaves no trace");
    assert_eq!(s.next_sample(), Some(2));
    // Continue in a fresh session from the film, as a resumed checkpoint does.
    let film = s.into_film();
    let mut r = RenderSession::with_film(&scene, &o, film, 2).unwrap();
    r.advance(2..7, &()).unwrap();
    assert_eq!(bits(r.film()), whole);
}

#[test]
fn observers_see_every_tile_and_all_the_work() {
    let scene = Scene::build(&scene()).unwrap();
    let mut s = RenderSession::new(&scene, &opts(2, 4)).unwrap();
    let obs = cancel_after(u64::MAX);
    let out = s.render_samples(0..7, &obs).unwrap();
    assert_eq!(obs.tiles.load(Ordering::SeqCst), s.tiles().len() as u64);
    let work = 13 * 9 * 7;
    assert_eq!(*obs.last_progress.lock().unwrap(), (work, work));
    assert_eq!(out.stats.paths, work);
    assert_eq!(out.film.samples_per_pixel(), 7);
    assert!(out.film.pixels().iter().all(|p| p.count == 7));
}

/// The films of disjoint windows, combined, have the bits of the whole render: each pixel
/// is rendered by one window, and the splats (light tracing, BDPT) add exactly wherever
/// they land.
#[test]
fn windows_combine_into_the_whole_render_bit_for_bit() {
    for kind in [IntegratorKind::Path, IntegratorKind::LightPath, IntegratorKind::Bdpt] {
        let mut d = scene();
        d.integrator.kind = kind;
        let scene = Scene::build(&d).unwrap();
        let whole = one_pass(&scene, &opts(2, 4));
        let windows = [
            Tile {
                x0: 0,
                y0: 0,
                x1: 13,
                y1: 2,
            },
            Tile {
                x0: 0,
                y0: 2,
                x1: 5,
                y1: 9,
            },
            Tile {
                x0: 5,
                y0: 2,
                x1: 13,
                y1: 9,
            },
        ];
        let films: Vec<Film> = windows
            .iter()
            .map(|w| {
                let mut s = RenderSession::new(&scene, &opts(1, 3)).unwrap();
                s.set_window(*w).unwrap();
                s.advance(0..7, &()).unwrap();
                s.into_film()
            })
            .collect();
        for order in [[0, 1, 2], [2, 0, 1]] {
            let mut film = films[order[0]].clone();
            for &i in &order[1..] {
                film.combine_disjoint(&films[i]).unwrap();
            }
            assert_eq!(bits(&film), bits(&whole), "{kind:?}, order {order:?}");
        }
        if kind != IntegratorKind::Path {
            // The first window's paths splat onto pixels outside it.
            assert!(films[0].splat_sums()[13 * 5..].iter().any(|s| !s.is_zero()), "{kind:?}");
        }
        let mut twice = films[0].clone();
        assert!(twice.combine_disjoint(&films[0]).is_err());
    }
    let scene = Scene::build(&scene()).unwrap();
    let mut s = RenderSession::new(&scene, &opts(1, 3)).unwrap();
    let outside = Tile {
        x0: 0,
        y0: 0,
        x1: 14,
        y1: 2,
    };
    assert!(matches!(s.set_window(outside), Err(RenderError::Window { .. })));
}
