//! MLT under the [`state_driver`](crate::state_driver) of `mcrender render` (a bootstrap,
//! then Markov chains; not samples per pixel): the bootstrap, then steps of mutations sized
//! to the time the driver gives (to end at the next checkpoint), the MLT state
//! ([`MltState`]: `b`, the chains, the splat sums) checkpointed in section `integrator.mlt`.
//! A chain stopped by a signal stops after a whole mutation and continues from there, so a
//! resumed render is bit-identical to one never stopped, whatever the thread counts.

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use mcrender_core::film::Film;
use mcrender_core::integrator::mlt::{self, MltSettings, MltState};
use mcrender_core::integrator::TraceStats;
use mcrender_core::scene::Scene;

use crate::state_driver::StateRender;

/// Mutations of the first step, before the time of one is known.
const FIRST_STEP: u64 = 4096;

/// An MLT render: its settings and the measured speed that sizes its steps.
pub struct MltRender {
    settings: MltSettings,
    /// Mutations wanted in all: `mutationsperpixel` per pixel.
    total: u64,
    /// The time of one mutation in the last step that made any.
    seconds_per_mutation: Option<f64>,
}

impl MltRender {
    /// The MLT render of `scene` (its MLT settings) on a `width` x `height` film.
    pub fn new(scene: &Scene, width: u32, height: u32) -> Self {
        let settings = MltSettings::from_scene(scene);
        let total = u64::from(settings.mutations_per_pixel) * u64::from(width) * u64::from(height);
        Self {
            settings,
            total,
            seconds_per_mutation: None,
        }
    }
}

impl StateRender for MltRender {
    type State = MltState;
    const NAME: &'static str = "mlt";
    const LABEL: &'static str = "MLT";
    const UNIT: &'static str = "mutation";
    const RATE_UNIT: &'static str = "mutations";

    fn new_state(&self, width: u32, height: u32) -> MltState {
        MltState::new(width, height)
    }

    fn restore(&self, bytes: &[u8], width: u32, height: u32) -> Result<MltState, String> {
        MltState::from_bytes(bytes, width, height, &self.settings)
    }

    fn state_bytes(&self, state: &MltState) -> Vec<u8> {
        state.to_bytes()
    }

    fn film(&self, state: &MltState) -> Film {
        state.film(&self.settings)
    }

    fn done(&self, state: &MltState) -> u64 {
        state.mutations()
    }

    fn total(&self) -> u64 {
        self.total
    }

    fn is_finished(&self, state: &MltState) -> bool {
        state.is_finished()
    }

    fn start(&mut self, scene: &Scene, state: &mut MltState, cancel: &AtomicBool) -> TraceStats {
        mlt::bootstrap(scene, &self.settings, state, cancel)
    }

    fn step(
        &mut self,
        scene: &Scene,
        state: &mut MltState,
        seconds: f64,
        progress: &(dyn Fn(u64) + Sync),
        cancel: &AtomicBool,
    ) -> Option<TraceStats> {
        let budget = self
            .seconds_per_mutation
            .map_or(FIRST_STEP, |t| ((seconds / t.max(1e-12)) as u64).max(1));
        let (before, t0) = (state.mutations(), Instant::now());
        let trace = mlt::advance(scene, &self.settings, state, budget, &|done, _| progress(done), cancel);
        let made = state.mutations() - before;
        if made > 0 {
            self.seconds_per_mutation = Some(t0.elapsed().as_secs_f64() / made as f64);
        }
        Some(trace)
    }

    fn paths(&self, units: u64) -> u64 {
        units
    }

    fn describe(&self, state: &MltState) -> String {
        format!(
            "MLT {} mutations per pixel ({} chains, b = {:.4}, {:.1}% accepted)",
            self.settings.mutations_per_pixel,
            self.settings.chains,
            state.b(),
            100.0 * state.accepted() as f64 / state.mutations().max(1) as f64,
        )
    }
}
