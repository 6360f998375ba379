//! `VecEnv`: many arenas stepped together across cores with the GIL released.

use crate::checks::{check_action, check_seed, value_error, SIDE};
use crate::env::{info, observation, rgb, step_seconds, surface_of, task_of, top_down, Tracked};
use numpy::ndarray::{Array1, Array4};
use numpy::{IntoPyArray, PyArray1, PyArray3, PyArray4, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use sec_playground::arena::Action;
use sec_playground::encoder::IMAGE;

/// `n` arenas of one task stepped in one call, across cores, with the GIL released. Each resets
/// itself on the call after its episode ended (Gymnasium's next-step autoreset): that call
/// ignores its action and returns the new episode's first observation with reward 0.
#[pyclass(module = "sec_playground._core", name = "VecEnv")]
pub(crate) struct PyVecEnv {
    arenas: Vec<Tracked>,
    ended: Vec<bool>,
}

#[pymethods]
impl PyVecEnv {
    #[new]
    #[pyo3(signature = (task, n, t=None, yaml=None, frame_skip=1, max_steps=None, surface="flat"))]
    fn new(
        task: &str,
        n: usize,
        t: Option<u32>,
        yaml: Option<&str>,
        frame_skip: u32,
        max_steps: Option<u64>,
        surface: &str,
    ) -> PyResult<Self> {
        if !(1..=4096).contains(&n) {
            return Err(value_error(format!("num_envs: {n} is out of range 1..=4096")));
        }
        let arena = Tracked::new(task_of(task, yaml)?, t, surface_of(surface)?, frame_skip, max_steps)?;
        Ok(PyVecEnv { arenas: vec![arena; n], ended: vec![false; n] })
    }

    /// Restarts every arena, arena i from `seeds[i]`: the observations, (n, 84, 84, 3).
    fn reset<'py>(&mut self, py: Python<'py>, seeds: Vec<u64>) -> PyResult<Bound<'py, PyArray4<u8>>> {
        if seeds.len() != self.arenas.len() {
            return Err(value_error(format!("seeds: {} seeds for {} envs", seeds.len(), self.arenas.len())));
        }
        for &s in &seeds {
            check_seed(s)?;
        }
        let obs = py.detach(|| {
            let mut obs = vec![0u8; self.arenas.len() * IMAGE];
            self.arenas.par_iter_mut().zip(obs.par_chunks_mut(IMAGE)).zip(&seeds).for_each(|((arena, o), &s)| {
                rgb(arena.reset(Some(s)), o);
            });
            obs
        });
        self.ended.iter_mut().for_each(|e| *e = false);
        Ok(Array4::from_shape_vec((self.arenas.len(), SIDE, SIDE, 3), obs).expect("n x 84 x 84 x 3").into_pyarray(py))
    }

    /// One action per arena: (observations, rewards, terminated, truncated).
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray1<'py, i64>,
    ) -> PyResult<(
        Bound<'py, PyArray4<u8>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyArray1<bool>>,
    )> {
        let actions = actions.as_slice().map_err(value_error)?;
        if actions.len() != self.arenas.len() {
            return Err(value_error(format!("actions: {} actions for {} envs", actions.len(), self.arenas.len())));
        }
        let actions: Vec<Action> = actions.iter().map(|&a| check_action(a)).collect::<PyResult<_>>()?;
        let n = self.arenas.len();
        let (obs, outcomes) = py.detach(|| {
            let mut obs = vec![0u8; n * IMAGE];
            let outcomes: Vec<(f64, bool, bool)> = self
                .arenas
                .par_iter_mut()
                .zip(obs.par_chunks_mut(IMAGE))
                .zip(self.ended.par_iter_mut())
                .zip(&actions)
                .map(|(((arena, o), ended), &a)| {
                    if *ended {
                        *ended = false;
                        rgb(arena.reset(None), o);
                        return (0.0, false, false);
                    }
                    let out = arena.advance(a).expect("a running episode takes a step");
                    *ended = out.terminated || out.truncated;
                    rgb(arena.env.observation(), o);
                    (out.reward, out.terminated, out.truncated)
                })
                .collect();
            (obs, outcomes)
        });
        let obs = Array4::from_shape_vec((n, SIDE, SIDE, 3), obs).expect("n x 84 x 84 x 3").into_pyarray(py);
        let rewards = Array1::from_iter(outcomes.iter().map(|o| o.0)).into_pyarray(py);
        let terminated = Array1::from_iter(outcomes.iter().map(|o| o.1)).into_pyarray(py);
        let truncated = Array1::from_iter(outcomes.iter().map(|o| o.2)).into_pyarray(py);
        Ok((obs, rewards, terminated, truncated))
    }

    /// Each arena's `info`, as the single env reports it.
    fn infos<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.arenas.iter().map(|a| info(py, a)).collect()
    }

    /// Arena `i` from above with its trail, `size` x `size` RGB bytes.
    #[pyo3(signature = (i, size=256))]
    fn top_down<'py>(&mut self, py: Python<'py>, i: usize, size: u32) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let n = self.arenas.len();
        let arena =
            self.arenas.get_mut(i).ok_or_else(|| value_error(format!("i: {i} is out of range 0..={}", n - 1)))?;
        top_down(py, arena, size)
    }

    /// Arena `i`'s camera now (84x84x3 bytes).
    fn observation<'py>(&mut self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let n = self.arenas.len();
        let arena =
            self.arenas.get_mut(i).ok_or_else(|| value_error(format!("i: {i} is out of range 0..={}", n - 1)))?;
        Ok(observation(py, &mut arena.env))
    }

    /// Per arena (seed, resets since it, this episode's actions, whether its next step resets it).
    fn get_state(&self) -> Vec<(u64, u64, Vec<u8>, bool)> {
        self.arenas.iter().zip(&self.ended).map(|(a, &e)| (a.seed, a.resets, a.actions.clone(), e)).collect()
    }

    /// Replays a `get_state`; a bad state raises and changes nothing.
    fn set_state(&mut self, state: Vec<(u64, u64, Vec<u8>, bool)>) -> PyResult<()> {
        if state.len() != self.arenas.len() {
            return Err(value_error(format!("state: {} arenas for {} envs", state.len(), self.arenas.len())));
        }
        let mut arenas = self.arenas.clone();
        for (arena, (seed, resets, actions, _)) in arenas.iter_mut().zip(&state) {
            arena.restore((*seed, *resets, actions.clone()))?;
        }
        self.arenas = arenas;
        self.ended = state.iter().map(|s| s.3).collect();
        Ok(())
    }

    #[getter]
    fn num_envs(&self) -> usize {
        self.arenas.len()
    }

    #[getter]
    fn step_seconds(&self) -> f64 {
        step_seconds(self.arenas[0].frame_skip)
    }

    /// The episode limit in env steps (0: none).
    #[getter]
    fn t(&self) -> u32 {
        self.arenas[0].env.t()
    }
}
