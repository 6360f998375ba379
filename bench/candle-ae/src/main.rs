//! One training step of the paper's autoencoder in candle (CPU), batch 64, for comparison with
//! `sec-train bench` (burn). SGD stands in for RMSprop (candle-nn has none); the optimiser's cost
//! is negligible next to the convolutions' forward and backward passes.

use candle_core::{DType, Device, Tensor};
use candle_nn::{conv2d, linear, Conv2dConfig, Module, Optimizer, VarBuilder, VarMap, SGD};
fn main() -> candle_core::Result<()> {
    let dev = Device::Cpu;
    let vm = VarMap::new();
    let vb = VarBuilder::from_varmap(&vm, DType::F32, &dev);
    let same = Conv2dConfig { padding: 1, ..Default::default() };
    let valid = Conv2dConfig::default();
    let e1 = conv2d(3, 16, 3, same, vb.pp("e1"))?;
    let e2 = conv2d(16, 32, 3, same, vb.pp("e2"))?;
    let e3 = conv2d(32, 32, 3, same, vb.pp("e3"))?;
    let ed = linear(3872, 20, vb.pp("ed"))?;
    let dd = linear(20, 3872, vb.pp("dd"))?;
    let d1 = conv2d(32, 32, 3, same, vb.pp("d1"))?;
    let d2 = conv2d(32, 32, 3, same, vb.pp("d2"))?;
    let d3 = conv2d(32, 16, 3, valid, vb.pp("d3"))?;
    let d4 = conv2d(16, 3, 3, same, vb.pp("d4"))?;
    let mut opt = SGD::new(vm.all_vars(), 1e-3)?;
    let x = Tensor::rand(0f32, 1f32, (64, 3, 84, 84), &dev)?;
    let step = |opt: &mut SGD| -> candle_core::Result<()> {
        let h = e1.forward(&x)?.relu()?.max_pool2d(2)?;
        let h = e2.forward(&h)?.relu()?.max_pool2d(2)?;
        // TensorFlow's `same` pooling takes 21 to 11: pad one row and column (values are >= 0).
        let h = e3.forward(&h)?.relu()?.pad_with_zeros(2, 0, 1)?.pad_with_zeros(3, 0, 1)?.max_pool2d(2)?;
        let e = ed.forward(&h.flatten_from(1)?)?.relu()?;
        let h = dd.forward(&e)?.reshape((64, 32, 11, 11))?;
        let h = d1.forward(&h)?.relu()?.upsample_nearest2d(22, 22)?;
        let h = d2.forward(&h)?.relu()?.upsample_nearest2d(44, 44)?;
        let h = d3.forward(&h)?.relu()?.upsample_nearest2d(84, 84)?;
        let y = d4.forward(&h)?.relu()?;
        let loss = (y - &x)?.sqr()?.mean_all()?;
        opt.backward_step(&loss)?;
        let _ = loss.to_scalar::<f32>()?;
        Ok(())
    };
    step(&mut opt)?;
    let t = std::time::Instant::now();
    let n = 5;
    for _ in 0..n {
        step(&mut opt)?;
    }
    let s = t.elapsed().as_secs_f64() / n as f64;
    println!("candle cpu: {:.3} s per batch of 64 = {:.1} frames/s", s, 64.0 / s);
    Ok(())
}
