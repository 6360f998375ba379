//! Whether the shortcuts that skip repeated work are on: the convolutions' window reuse
//! (`encoder::kernels::Repeats`), a run's frame cache (`encoder::cache`) and retrieval's reuse of
//! the last similarity row. Each gives the bits of computing in full, so they are always on;
//! builds with the `test-hooks` feature can turn them off for one thread, to compare a run with
//! itself computed in full.

#[cfg(feature = "test-hooks")]
thread_local! {
    static ON: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// Test hook: turns every reuse off (or on again) for this thread.
#[cfg(feature = "test-hooks")]
pub fn set(on: bool) {
    ON.with(|o| o.set(on));
}

/// Whether work may be reused on this thread.
pub(crate) fn on() -> bool {
    #[cfg(feature = "test-hooks")]
    return ON.with(|o| o.get());
    #[allow(unreachable_code)]
    true
}
