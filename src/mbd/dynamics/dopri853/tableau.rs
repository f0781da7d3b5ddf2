//! The Butcher tableau of DOP853 (Dormand & Prince's 8(5,3) pair as Hairer, Nørsett &
//! Wanner publish it with their code `dop853`, *Solving ODEs I*, §II.10): twelve stages,
//! the eighth-order weights, and the two embedded estimators [`super::Dopri853`] combines.
//! The coefficients are the published 30-digit decimals (rounded to f64 on parsing, so
//! they can be checked against the table digit for digit); the tests below check them
//! against the order conditions they must satisfy, which a mistyped digit breaks.

// The published digits are kept as printed rather than cut to 17: the source stays
// comparable with the table, and the parse rounds them to the same f64 either way.
#![allow(clippy::excessive_precision)]

/// Stages per step (the FSAL stage of the published code is not used: the next step's
/// first stage is evaluated at the projected state instead).
pub const STAGES: usize = 12;

/// The nodes cᵢ.
pub const C: [f64; STAGES] = [
    0.0,
    0.526001519587677318785587544488e-1,
    0.789002279381515978178381316732e-1,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
];

/// The coupling coefficients aᵢⱼ, row by row, as (j, aᵢⱼ) over the nonzero entries (more
/// than a third of the lower triangle is zero).
pub const A: [&[(usize, f64)]; STAGES] = [
    &[],
    &[(0, 5.26001519587677318785587544488e-2)],
    &[
        (0, 1.97250569845378994544595329183e-2),
        (1, 5.91751709536136983633785987549e-2),
    ],
    &[
        (0, 2.95875854768068491816892993775e-2),
        (2, 8.87627564304205475450678981324e-2),
    ],
    &[
        (0, 2.41365134159266685502369798665e-1),
        (2, -8.84549479328286085344864962717e-1),
        (3, 9.24834003261792003115737966543e-1),
    ],
    &[
        (0, 3.7037037037037037037037037037e-2),
        (3, 1.70828608729473871279604482173e-1),
        (4, 1.25467687566822425016691814123e-1),
    ],
    &[
        (0, 3.7109375e-2),
        (3, 1.70252211019544039314978060272e-1),
        (4, 6.02165389804559606850219397283e-2),
        (5, -1.7578125e-2),
    ],
    &[
        (0, 3.70920001185047927108779319836e-2),
        (3, 1.70383925712239993810214054705e-1),
        (4, 1.07262030446373284651809199168e-1),
        (5, -1.53194377486244017527936158236e-2),
        (6, 8.27378916381402288758473766002e-3),
    ],
    &[
        (0, 6.24110958716075717114429577812e-1),
        (3, -3.36089262944694129406857109825),
        (4, -8.68219346841726006818189891453e-1),
        (5, 2.75920996994467083049415600797e1),
        (6, 2.01540675504778934086186788979e1),
        (7, -4.34898841810699588477366255144e1),
    ],
    &[
        (0, 4.77662536438264365890433908527e-1),
        (3, -2.48811461997166764192642586468),
        (4, -5.90290826836842996371446475743e-1),
        (5, 2.12300514481811942347288949897e1),
        (6, 1.52792336328824235832596922938e1),
        (7, -3.32882109689848629194453265587e1),
        (8, -2.03312017085086261358222928593e-2),
    ],
    &[
        (0, -9.3714243008598732571704021658e-1),
        (3, 5.18637242884406370830023853209),
        (4, 1.09143734899672957818500254654),
        (5, -8.14978701074692612513997267357),
        (6, -1.85200656599969598641566180701e1),
        (7, 2.27394870993505042818970056734e1),
        (8, 2.49360555267965238987089396762),
        (9, -3.0467644718982195003823669022),
    ],
    &[
        (0, 2.27331014751653820792359768449),
        (3, -1.05344954667372501984066689879e1),
        (4, -2.00087205822486249909675718444),
        (5, -1.79589318631187989172765950534e1),
        (6, 2.79488845294199600508499808837e1),
        (7, -2.85899827713502369474065508674),
        (8, -8.87285693353062954433549289258),
        (9, 1.23605671757943030647266201528e1),
        (10, 6.43392746015763530355970484046e-1),
    ],
];

/// The eighth-order weights bᵢ (nonzero entries).
pub const B: [(usize, f64); 8] = [
    (0, 5.42937341165687622380535766363e-2),
    (5, 4.45031289275240888144113950566),
    (6, 1.89151789931450038304281599044),
    (7, -5.8012039600105847814672114227),
    (8, 3.1116436695781989440891606237e-1),
    (9, -1.52160949662516078556178806805e-1),
    (10, 2.01365400804030348374776537501e-1),
    (11, 4.47106157277725905176885569043e-2),
];

/// The embedded third-order weights (`bhh` of the published code): b − BHH estimates
/// the error of a third-order solution, O(h⁴).
pub const BHH: [(usize, f64); 3] = [
    (0, 0.244094488188976377952755905512),
    (8, 0.733846688281611857341361741547),
    (11, 0.220588235294117647058823529412e-1),
];

/// b minus the embedded fifth-order weights (`er` of the published code): the error of
/// a fifth-order solution, O(h⁶).
pub const ER: [(usize, f64); 8] = [
    (0, 0.1312004499419488073250102996e-1),
    (5, -0.1225156446376204440720569753e1),
    (6, -0.4957589496572501915214079952),
    (7, 0.1664377182454986536961530415e1),
    (8, -0.3503288487499736816886487290),
    (9, 0.3341791187130174790297318841),
    (10, 0.8192320648511571246570742613e-1),
    (11, -0.2235530786388629525884427845e-1),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Σ wᵢ·cᵢᵏ over sparse weights.
    fn moment(w: &[(usize, f64)], k: i32) -> f64 {
        w.iter().map(|&(i, x)| x * C[i].powi(k)).sum()
    }

    #[test]
    fn each_row_sums_to_its_node() {
        for (i, row) in A.iter().enumerate() {
            // To the rounding of the entries (up to 44 in size, so 1e-14 in a row).
            let sum: f64 = row.iter().map(|&(_, a)| a).sum();
            let size: f64 = row.iter().map(|&(_, a)| a.abs()).sum();
            let off = (sum - C[i]).abs();
            assert!(
                off <= 4.0 * f64::EPSILON * size,
                "row {i}: {sum} vs c = {}",
                C[i]
            );
            assert!(row.iter().all(|&(j, _)| j < i), "row {i} is explicit");
        }
    }

    #[test]
    fn weights_integrate_polynomials_to_their_orders() {
        // The bushy-tree conditions Σ bᵢ·cᵢᵏ = 1/(k + 1): through degree 7 for the
        // eighth-order weights, degree 2 for the third-order ones; the fifth-order
        // weights integrate through degree 4, so their difference to b does not see it.
        for k in 0..8 {
            let m = moment(&B, k);
            assert!(
                (m - 1.0 / (k + 1) as f64).abs() < 1e-14,
                "b, degree {k}: {m}"
            );
        }
        for k in 0..3 {
            let m = moment(&BHH, k);
            assert!(
                (m - 1.0 / (k + 1) as f64).abs() < 1e-14,
                "bhh, degree {k}: {m}"
            );
        }
        for k in 0..5 {
            let m = moment(&ER, k);
            assert!(m.abs() < 1e-14, "er, degree {k}: {m}");
        }
        // And they are estimators: both differ from b at the next degree.
        assert!((moment(&BHH, 3) - 0.25).abs() > 1e-3);
        assert!(moment(&ER, 5).abs() > 1e-6);
    }

    #[test]
    fn stage_values_are_second_order_accurate_where_the_method_needs_it() {
        // Σⱼ aᵢⱼ·cⱼ = cᵢ²/2 for every stage from the third (the simplifying assumption
        // the eighth-order conditions of the pair are built on): it checks each aᵢⱼ
        // again, weighted differently from the row sums.
        for (i, row) in A.iter().enumerate().skip(2) {
            let m: f64 = row.iter().map(|&(j, a)| a * C[j]).sum();
            assert!(
                (m - C[i] * C[i] / 2.0).abs() < 1e-14,
                "row {i}: {m} vs {}",
                C[i] * C[i] / 2.0
            );
        }
    }
}
