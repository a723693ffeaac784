//! SPPM under the [`state_driver`](crate::state_driver) of `mcrender render` (iterations of
//! camera and photon passes, not samples per pixel): one iteration a step, the per-pixel
//! SPPM state ([`SppmState`]) checkpointed in section `integrator.sppm`. An iteration cut
//! short by a signal is dropped whole, so a resumed render is bit-identical to one never
//! stopped, whatever the thread counts.

use std::sync::atomic::AtomicBool;

use mcrender_core::film::Film;
use mcrender_core::integrator::sppm::{self, SppmSettings, SppmState};
use mcrender_core::integrator::TraceStats;
use mcrender_core::scene::Scene;

use crate::state_driver::StateRender;

/// An SPPM render: its settings.
pub struct SppmRender {
    settings: SppmSettings,
}

impl SppmRender {
    /// The SPPM render of `scene` (its SPPM settings).
    pub fn new(scene: &Scene) -> Self {
        Self {
            settings: SppmSettings::from_scene(scene),
        }
    }
}

impl StateRender for SppmRender {
    type State = SppmState;
    const NAME: &'static str = "sppm";
    const LABEL: &'static str = "SPPM";
    const UNIT: &'static str = "iteration";
    const RATE_UNIT: &'static str = "photons";

    fn new_state(&self, width: u32, height: u32) -> SppmState {
        SppmState::new(width, height, &self.settings)
    }

    fn restore(&self, bytes: &[u8], width: u32, height: u32) -> Result<SppmState, String> {
        SppmState::from_bytes(bytes, width, height)
    }

    fn state_bytes(&self, state: &SppmState) -> Vec<u8> {
        state.to_bytes()
    }

    fn film(&self, state: &SppmState) -> Film {
        state.film(&self.settings)
    }

    fn done(&self, state: &SppmState) -> u64 {
        u64::from(state.iterations_done())
    }

    fn total(&self) -> u64 {
        u64::from(self.settings.iterations)
    }

    fn is_finished(&self, state: &SppmState) -> bool {
        state.iterations_done() >= self.settings.iterations
    }

    /// One iteration, whatever `seconds`.
    fn step(
        &mut self,
        scene: &Scene,
        state: &mut SppmState,
        _seconds: f64,
        _progress: &(dyn Fn(u64) + Sync),
        cancel: &AtomicBool,
    ) -> Option<TraceStats> {
        sppm::iterate(scene, &self.settings, state, cancel)
    }

    fn paths(&self, units: u64) -> u64 {
        units * self.settings.photons_per_iteration
    }

    fn describe(&self, state: &SppmState) -> String {
        format!(
            "SPPM {} iterations x {} photons",
            state.iterations_done(),
            self.settings.photons_per_iteration
        )
    }
}
