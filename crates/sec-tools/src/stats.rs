//! The statistics the report needs: means with t-based 95% intervals, the Mann-Whitney U test
//! the authors used (two-sided; exact without ties, else normal with tie correction), and the
//! trailing moving window of the learning curves.

pub fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

/// Sample standard deviation (0 for fewer than two values).
pub fn sd(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return 0.0;
    }
    let m = mean(x);
    (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (x.len() - 1) as f64).sqrt()
}

pub fn se(x: &[f64]) -> f64 {
    sd(x) / (x.len() as f64).sqrt()
}

/// Student's t quantile 0.975 for `df` degrees of freedom.
pub fn t975(df: usize) -> f64 {
    const T: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
        2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
    ];
    match df {
        0 => f64::NAN,
        1..=30 => T[df - 1],
        31..=60 => 2.000,
        61..=120 => 1.980,
        _ => 1.960,
    }
}

/// Half-width of the 95% confidence interval of the mean.
pub fn ci95(x: &[f64]) -> f64 {
    if x.len() < 2 {
        return f64::NAN;
    }
    t975(x.len() - 1) * se(x)
}

/// Mann-Whitney U of `a` against `b` and its two-sided p-value.
pub fn mann_whitney(a: &[f64], b: &[f64]) -> (f64, f64) {
    let (n1, n2) = (a.len(), b.len());
    if n1 == 0 || n2 == 0 {
        return (f64::NAN, f64::NAN);
    }
    // Midranks of the pooled sample.
    let mut pooled: Vec<(f64, usize)> = a.iter().map(|&v| (v, 0)).chain(b.iter().map(|&v| (v, 1))).collect();
    pooled.sort_by(|x, y| x.0.total_cmp(&y.0));
    let n = pooled.len();
    let (mut rank_a, mut ties, mut i) = (0.0, 0.0, 0);
    while i < n {
        let mut j = i;
        while j + 1 < n && pooled[j + 1].0 == pooled[i].0 {
            j += 1;
        }
        let rank = (i + j) as f64 / 2.0 + 1.0;
        let t = (j - i + 1) as f64;
        ties += t * t * t - t;
        rank_a += pooled[i..=j].iter().filter(|p| p.1 == 0).count() as f64 * rank;
        i = j + 1;
    }
    let u = rank_a - (n1 * (n1 + 1)) as f64 / 2.0;
    let p = if ties == 0.0 && n1 <= 30 && n2 <= 30 {
        exact_p(u as usize, n1, n2)
    } else {
        let mu = (n1 * n2) as f64 / 2.0;
        let (n1f, n2f, nf) = (n1 as f64, n2 as f64, n as f64);
        let var = n1f * n2f / 12.0 * ((nf + 1.0) - ties / (nf * (nf - 1.0)));
        if var <= 0.0 {
            1.0
        } else {
            // Continuity-corrected normal approximation.
            let z = ((u - mu).abs() - 0.5).max(0.0) / var.sqrt();
            libm::erfc(z / std::f64::consts::SQRT_2).min(1.0)
        }
    };
    (u, p)
}

/// Two-sided exact p-value of U = `u` for samples of `n1` and `n2` without ties.
fn exact_p(u: usize, n1: usize, n2: usize) -> f64 {
    // f[i][j][v]: orderings of i a's and j b's in which a's beat b's v times. The largest value
    // is an a (beating all j b's) or a b: f(i, j, v) = f(i - 1, j, v - j) + f(i, j - 1, v).
    let max = n1 * n2;
    let mut f = vec![vec![vec![0.0f64; max + 1]; n2 + 1]; n1 + 1];
    for row in f.iter_mut() {
        row[0][0] = 1.0;
    }
    for cell in f[0].iter_mut() {
        cell[0] = 1.0;
    }
    for i in 1..=n1 {
        for j in 1..=n2 {
            for v in 0..=i * j {
                let take_a = if v >= j { f[i - 1][j][v - j] } else { 0.0 };
                f[i][j][v] = take_a + f[i][j - 1][v];
            }
        }
    }
    let dist = &f[n1][n2];
    let total: f64 = dist.iter().sum();
    let lower: f64 = dist[..=u].iter().sum::<f64>() / total;
    let upper: f64 = dist[u..].iter().sum::<f64>() / total;
    (2.0 * lower.min(upper)).min(1.0)
}

/// Trailing moving mean over `w` values (the first ones average what there is).
pub fn moving_mean(x: &[f64], w: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(x.len());
    let mut sum = 0.0;
    for i in 0..x.len() {
        sum += x[i];
        if i >= w {
            sum -= x[i - w];
        }
        out.push(sum / (i + 1).min(w) as f64);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mann_whitney_matches_hand_computed_values() {
        // Complete separation of 5 and 5: U = 0, exact p = 2 / C(10, 5) = 2 / 252.
        let (u, p) = mann_whitney(&[1.0, 2.0, 3.0, 4.0, 5.0], &[6.0, 7.0, 8.0, 9.0, 10.0]);
        assert_eq!(u, 0.0);
        assert!((p - 2.0 / 252.0).abs() < 1e-12, "{p}");
        // a = {1, 4}, b = {2, 3}: U = 0 + 2 = 2 = n1 n2 / 2, p = 1.
        let (u, p) = mann_whitney(&[1.0, 4.0], &[2.0, 3.0]);
        assert_eq!((u, p), (2.0, 1.0));
        // With ties the normal approximation: identical samples give p = 1.
        let (u, p) = mann_whitney(&[1.0, 1.0, 2.0], &[1.0, 1.0, 2.0]);
        assert_eq!((u, p), (4.5, 1.0));
    }

    #[test]
    fn intervals_and_windows() {
        let x = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(mean(&x), 2.5);
        assert!((sd(&x) - (5.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert!((ci95(&x) - 3.182 * sd(&x) / 2.0).abs() < 1e-12);
        assert_eq!(moving_mean(&[2.0, 4.0, 6.0, 8.0], 2), vec![2.0, 3.0, 5.0, 7.0]);
    }
}
