//! Per-target dispatch, written once. The hot kernels are plain Rust whose summation order is
//! fixed; on x86-64 the same code is also compiled with AVX2 enabled and picked at run time when
//! the CPU has it, so only the instructions differ, never the bits. wasm builds choose at compile
//! time (`simd128` or not) and need no run-time check.

/// Declares `fn NAME`, which runs `BODY` (an `#[inline(always)]` function with the same
/// parameters) compiled for AVX2 where the CPU has it, and as it is otherwise:
///
/// `avx2_dispatch! { fn conv_pass<const CI: usize>(x: &[f32], out: &mut [f32]) => conv_pass_any }`
macro_rules! avx2_dispatch {
    ($(#[$attr:meta])* $vis:vis fn $name:ident $(<$(const $c:ident: usize),+>)?
        ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? => $body:ident) => {
        $(#[$attr])*
        #[allow(clippy::too_many_arguments)]
        $vis fn $name $(<$(const $c: usize),+>)? ($($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2")]
                #[allow(clippy::too_many_arguments)]
                unsafe fn avx2 $(<$(const $c: usize),+>)? ($($arg: $ty),*) $(-> $ret)? {
                    $body $(::<$($c),+>)? ($($arg),*)
                }
                if $crate::dispatch::avx2() {
                    // SAFETY: the CPU supports AVX2, checked just above.
                    return unsafe { avx2 $(::<$($c),+>)? ($($arg),*) };
                }
            }
            $body $(::<$($c),+>)? ($($arg),*)
        }
    };
}
pub(crate) use avx2_dispatch;

/// Whether the AVX2 copies of the kernels run here: an x86-64 CPU with AVX2 (checked at run time,
/// the answer cached by std). Every hand-written AVX2 kernel is picked through this.
#[inline]
pub(crate) fn avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Which copies of the hot kernels this build runs on this machine: "avx2", "simd128" (a wasm
/// build with SIMD) or "scalar". The bits are the same on each; a run's record names it.
pub fn kernel_path() -> &'static str {
    if avx2() {
        "avx2"
    } else if cfg!(all(target_arch = "wasm32", target_feature = "simd128")) {
        "simd128"
    } else {
        "scalar"
    }
}

#[cfg(test)]
mod tests {
    /// The path named is the one the kernels take: AVX2 exactly where the CPU has it.
    #[test]
    fn the_kernel_path_names_the_copies_that_run() {
        #[cfg(target_arch = "x86_64")]
        assert_eq!(super::kernel_path() == "avx2", std::is_x86_feature_detected!("avx2"));
        #[cfg(not(target_arch = "x86_64"))]
        assert_ne!(super::kernel_path(), "avx2");
    }
}
