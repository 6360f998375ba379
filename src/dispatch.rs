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
                if std::is_x86_feature_detected!("avx2") {
                    // SAFETY: the CPU supports AVX2, checked just above.
                    return unsafe { avx2 $(::<$($c),+>)? ($($arg),*) };
                }
            }
            $body $(::<$($c),+>)? ($($arg),*)
        }
    };
}
pub(crate) use avx2_dispatch;
