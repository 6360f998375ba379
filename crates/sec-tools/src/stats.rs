//! The statistics the report needs: means with t-based 95% intervals, the Mann-Whitney U test
//! the authors used (two-sided; exact without ties, else normal with tie correction), and the
//! trailing moving window of the learning curves.

/// The arithmetic mean (NaN of nothing).
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

/// The standard error of the mean.
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
    let pooled: Vec<f64> = a.iter().chain(b).copied().collect();
    let (ranks, ties) = midranks(&pooled);
    let rank_a: f64 = ranks[..n1].iter().sum();
    let n = pooled.len();
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

/// The rank of each value of `x` (1 for the smallest; tied values share their mean rank) and the
/// ties' correction term, the sum over groups of t^3 - t.
fn midranks(x: &[f64]) -> (Vec<f64>, f64) {
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_by(|&i, &j| x[i].total_cmp(&x[j]));
    let (mut ranks, mut ties, mut i) = (vec![0.0; x.len()], 0.0, 0);
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && x[order[j + 1]] == x[order[i]] {
            j += 1;
        }
        let t = (j - i + 1) as f64;
        ties += t * t * t - t;
        for &k in &order[i..=j] {
            ranks[k] = (i + j) as f64 / 2.0 + 1.0;
        }
        i = j + 1;
    }
    (ranks, ties)
}

/// Spearman's rank correlation of paired `x` and `y`: Pearson's correlation of their midranks
/// (NaN with fewer than two pairs or a constant side).
pub fn spearman(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len(), "Spearman's correlation pairs its samples");
    let (rx, ry) = (midranks(x).0, midranks(y).0);
    let (mx, my) = (mean(&rx), mean(&ry));
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in rx.iter().zip(&ry) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    sxy / (sxx * syy).sqrt()
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

/// The `q` quantile of `x` (0 <= q <= 1) by linear interpolation between order statistics
/// (numpy's default); NaN for no values.
pub fn quantile(x: &[f64], q: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    let h = (v.len() - 1) as f64 * q;
    let (lo, frac) = (h.floor() as usize, h - h.floor());
    if lo + 1 < v.len() {
        v[lo] + frac * (v[lo + 1] - v[lo])
    } else {
        v[lo]
    }
}

/// Two-sided Fisher's exact test of the 2x2 table [[a, b], [c, d]] (successes and failures of
/// two samples): the probability, with the margins fixed, of every table no more likely than
/// this one (scipy's rule, with its relative tolerance for ties of probability).
pub fn fisher_exact(a: usize, b: usize, c: usize, d: usize) -> f64 {
    let (row1, col1, n) = (a + b, a + c, a + b + c + d);
    let ln_choose = |n: usize, k: usize| ln_factorial(n) - ln_factorial(k) - ln_factorial(n - k);
    let ln_p = |x: usize| ln_choose(col1, x) + ln_choose(n - col1, row1 - x) - ln_choose(n, row1);
    let lo = row1.saturating_sub(n - col1);
    let hi = row1.min(col1);
    let observed = ln_p(a);
    let p: f64 = (lo..=hi).map(ln_p).filter(|&l| l <= observed + 1e-7).map(f64::exp).sum();
    p.min(1.0)
}

fn ln_factorial(n: usize) -> f64 {
    (2..=n).map(|k| (k as f64).ln()).sum()
}

/// Jonckheere-Terpstra's test of a decreasing trend over ordered groups: the statistic (pairs
/// from an earlier group above one from a later group, ties counting a half) and its one-sided p
/// from `permutations` random reassignments of the pooled values to groups of the same sizes,
/// drawn from ChaCha8 with `seed` (so the p is a pure function of the data): (1 + the
/// permutations whose statistic is at least the observed) / (1 + permutations).
pub fn jonckheere_decreasing(groups: &[Vec<f64>], permutations: usize, seed: u64) -> (f64, f64) {
    use rand::seq::SliceRandom;
    use rand::SeedableRng;
    let statistic = |g: &[&[f64]]| {
        let mut j = 0.0;
        for (a, earlier) in g.iter().enumerate() {
            for later in &g[a + 1..] {
                for x in earlier.iter() {
                    for y in later.iter() {
                        j += if x > y {
                            1.0
                        } else if x == y {
                            0.5
                        } else {
                            0.0
                        };
                    }
                }
            }
        }
        j
    };
    let sizes: Vec<usize> = groups.iter().map(Vec::len).collect();
    let split = |pooled: &[f64]| -> f64 {
        let mut parts = Vec::with_capacity(sizes.len());
        let mut at = 0;
        for &n in &sizes {
            parts.push(&pooled[at..at + n]);
            at += n;
        }
        statistic(&parts)
    };
    let mut pooled: Vec<f64> = groups.iter().flatten().copied().collect();
    let observed = split(&pooled);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut at_least = 0usize;
    for _ in 0..permutations {
        pooled.shuffle(&mut rng);
        at_least += (split(&pooled) >= observed) as usize;
    }
    (observed, (1 + at_least) as f64 / (1 + permutations) as f64)
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
    fn jonckheere_counts_ordered_pairs_and_its_permutation_p_is_the_exact_one_within_noise() {
        // Two groups of two, wholly ordered: J = 4, reached by 1 of the C(4, 2) = 6 assignments.
        let (j, p) = jonckheere_decreasing(&[vec![3.0, 4.0], vec![1.0, 2.0]], 20_000, 1);
        assert_eq!(j, 4.0);
        assert!((p - 1.0 / 6.0).abs() < 0.01, "{p}");
        // Ties count a half.
        assert_eq!(jonckheere_decreasing(&[vec![1.0], vec![1.0]], 0, 1).0, 0.5);
        // Four groups of ten falling: tiny p; rising: p near 1; the same seed, the same p.
        let groups = |step: f64| {
            (0..4).map(|g| (0..10).map(|i| g as f64 * step + i as f64 * 0.1).collect()).collect::<Vec<Vec<f64>>>()
        };
        let (_, falling) = jonckheere_decreasing(&groups(-1.0), 2000, 7);
        let (_, rising) = jonckheere_decreasing(&groups(1.0), 2000, 7);
        assert!(falling < 0.001 && rising > 0.99, "{falling} {rising}");
        assert_eq!(jonckheere_decreasing(&groups(-0.05), 500, 3), jonckheere_decreasing(&groups(-0.05), 500, 3));
    }

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
    fn spearman_matches_hand_computed_values() {
        // Monotone but not linear: rank correlation 1; reversed: -1.
        assert_eq!(spearman(&[1.0, 2.0, 3.0, 4.0], &[1.0, 10.0, 100.0, 1000.0]), 1.0);
        assert_eq!(spearman(&[1.0, 2.0, 3.0, 4.0], &[4.0, 3.0, 2.0, 1.0]), -1.0);
        // Ranks (1, 2, 3, 4, 5) and (2, 1, 4, 3, 5): 1 - 6 * 4 / (5 * 24) = 0.8.
        assert!((spearman(&[1.0, 2.0, 3.0, 4.0, 5.0], &[20.0, 10.0, 40.0, 30.0, 50.0]) - 0.8).abs() < 1e-12);
        // Ties share their mean rank: x ranks (1.5, 1.5, 3), y (1, 2, 3); r = 1.5 / sqrt(1.5 * 2).
        let r = spearman(&[1.0, 1.0, 2.0], &[1.0, 2.0, 3.0]);
        assert!((r - 0.75f64.sqrt()).abs() < 1e-12, "{r}");
        assert!(spearman(&[1.0, 1.0], &[1.0, 2.0]).is_nan());
    }

    #[test]
    fn quantiles_and_fisher_match_numpy_and_scipy() {
        // numpy.quantile([1, 2, 3, 4], 0.95) = 3.85; one value is its own quantile.
        assert!((quantile(&[4.0, 1.0, 3.0, 2.0], 0.95) - 3.85).abs() < 1e-12);
        assert_eq!(quantile(&[7.0], 0.95), 7.0);
        assert!(quantile(&[], 0.5).is_nan());
        // scipy.stats.fisher_exact([[8, 2], [1, 5]]).pvalue = 0.034965034965034975 (and below)
        assert!((fisher_exact(8, 2, 1, 5) - 0.034965034965034975).abs() < 1e-12);
        // [[3, 1], [1, 3]]: 0.48571428571428565; equal tables: 1.
        assert!((fisher_exact(3, 1, 1, 3) - 0.4857142857142857).abs() < 1e-12);
        assert_eq!(fisher_exact(5, 5, 5, 5), 1.0);
        // [[18, 2], [4, 6]]: 0.007234844116403337.
        assert!((fisher_exact(18, 2, 4, 6) - 0.007234844116403337).abs() < 1e-12);
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
