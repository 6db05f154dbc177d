use super::*;

/// Quantising rounds to the nearest step, as the floor of the value
/// plus a half does, at and around every half step, and clamps.
#[test]
fn quantising_rounds_to_the_nearest_step() {
    let floor = |v: f32| (f64::from(v).clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8;
    let mut values = vec![f32::NAN, -0.0, -1.0, 2.0, f32::INFINITY, f32::NEG_INFINITY];
    for k in 0..=510 {
        let half = k as f32 / 510.0;
        values.extend([half, f32::from_bits(half.to_bits() + 1), half.next_down()]);
    }
    for v in values {
        assert_eq!(quantise(v), floor(v), "{v:e}");
    }
    assert_eq!((quantise(0.5 / 255.0), quantise(1.0)), (1, 255));
}

/// The first 2^m points are stratified in x and in y: each of the 2^m
/// columns and rows holds one.
#[test]
fn the_sequence_is_stratified_in_every_power_of_two_prefix() {
    for m in 0..=8 {
        let n = 1u32 << m;
        let (mut xs, mut ys): (Vec<u32>, Vec<u32>) = (0..n)
            .map(sobol)
            .map(|(x, y)| (x * n / 256, y * n / 256))
            .unzip();
        xs.sort_unstable();
        ys.sort_unstable();
        assert_eq!(xs, (0..n).collect::<Vec<_>>(), "columns of {n}");
        assert_eq!(ys, (0..n).collect::<Vec<_>>(), "rows of {n}");
    }
}

/// Every odd count of samples is centred in the pixel, every sample
/// lies inside it, and no two coincide; the first five are the centre
/// and a rotated grid.
#[test]
fn odd_counts_of_samples_are_centred_in_the_pixel() {
    let all: Vec<_> = (0..Contrast::MAX_SAMPLES).map(sample_at).collect();
    for n in (1..=Contrast::MAX_SAMPLES).step_by(2) {
        let (sx, sy) = all[..n as usize]
            .iter()
            .fold((0, 0), |(a, b), (x, y)| (a + x, b + y));
        assert_eq!((sx, sy), (n * 256, n * 256), "{n} samples");
    }
    assert!(all
        .iter()
        .all(|&(x, y)| (1..512).contains(&x) && (1..512).contains(&y)));
    let mut distinct = all.clone();
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(distinct.len(), all.len());
    let mut columns: Vec<_> = all[1..5].iter().map(|p| p.0 / 128).collect();
    let mut rows: Vec<_> = all[1..5].iter().map(|p| p.1 / 128).collect();
    columns.sort_unstable();
    rows.sort_unstable();
    assert_eq!((columns, rows), (vec![0, 1, 2, 3], vec![0, 1, 2, 3]));
}

/// Samples 1..=64 are the centres of the pixel's 8×8 lattice: the
/// first 16 one in each cell of a 4×4 grid and two in each row and
/// column of the lattice, the first 32 one of its two colours as a
/// checkerboard, the first 64 all of it.
#[test]
fn the_first_sixty_four_samples_fill_the_lattice_level_by_level() {
    let cells: Vec<(u32, u32)> = (1..=64)
        .map(sample_at)
        .map(|(x, y)| {
            assert_eq!((x % 64, y % 64), (32, 32), "a cell's centre");
            (x / 64, y / 64)
        })
        .collect();
    let mut grid: Vec<_> = cells[..16].iter().map(|&(x, y)| (x / 2, y / 2)).collect();
    grid.sort_unstable();
    grid.dedup();
    assert_eq!(grid.len(), 16, "one in each cell of the 4×4 grid");
    for i in 0..8 {
        assert_eq!(
            cells[..16].iter().filter(|c| c.0 == i).count(),
            2,
            "column {i}"
        );
        assert_eq!(
            cells[..16].iter().filter(|c| c.1 == i).count(),
            2,
            "row {i}"
        );
    }
    assert!(cells[..32].iter().all(|&(x, y)| (x + y) % 2 == 0));
    let mut all = cells.clone();
    all.sort_unstable();
    all.dedup();
    assert_eq!(all.len(), 64);
}

fn contrast(compare_trees: bool) -> Contrast {
    Contrast {
        thresholds: [0.4, 0.3, 0.6],
        max_samples: 33,
        compare_trees,
        range: None,
    }
}

/// Mitchell's contrast, per channel, in integers: a range passes only
/// above its channel's threshold.
#[test]
fn the_contrast_test_compares_each_channel_with_its_threshold() {
    let c = contrast(false);
    // (hi − lo)/(hi + lo): 60/140 = 0.43 > 0.4 in red.
    assert!(c.passes([40, 0, 0], [100, 0, 0]));
    // 40/160 = 0.25 < 0.4.
    assert!(!c.passes([60, 0, 0], [100, 0, 0]));
    // The same range passes green's 0.3 but not blue's 0.6.
    assert!(c.passes([0, 40, 0], [0, 100, 0]));
    assert!(!c.passes([0, 0, 40], [0, 0, 100]));
    // Black everywhere: no contrast.
    assert!(!c.passes([0; 3], [0; 3]));
    assert_eq!(c.levels(), vec![1, 5, 17, 33]);
    assert_eq!(
        Contrast {
            max_samples: 4,
            ..c
        }
        .levels(),
        vec![1, 4]
    );
    assert_eq!(
        Contrast {
            max_samples: 65,
            ..c
        }
        .levels(),
        vec![1, 5, 17, 65]
    );
}

fn pixel(v: u8, samples: u32, trees_differ: bool) -> Pixel {
    Pixel {
        samples,
        lo: [v; 3],
        hi: [v; 3],
        word: 0,
        trees_differ,
    }
}

/// The range test: a pixel's own samples pass it by their range over
/// the square root of their count; after the centres a pixel goes on
/// beside a neighbour of eight that differs from it, after the next
/// level beside one of four whose own samples pass.
#[test]
fn the_range_test_weighs_a_range_by_the_samples_behind_it() {
    let c = Contrast {
        range: Some(20.0 / 255.0),
        ..contrast(false)
    };
    // A 3×3 image of centres, the bottom-right 21 steps brighter: the
    // pixels beside it go on, the others do not.
    let mut image: Vec<Pixel> = (0..9).map(|_| pixel(50, 1, false)).collect();
    image[8] = pixel(71, 1, false);
    assert_eq!(c.next(0, &image, 3, &all(&image)), vec![4, 5, 7, 8]);
    image[8] = pixel(70, 1, false);
    assert_eq!(c.next(0, &image, 3, &all(&image)), Vec::<u32>::new());
    // A dim pixel: Mitchell's contrast passes 2 against 1, the range
    // test does not.
    let mut dim: Vec<Pixel> = (0..9).map(|_| pixel(1, 1, false)).collect();
    dim[8] = pixel(2, 1, false);
    assert_eq!(contrast(false).next(0, &dim, 3, &[8]), vec![8]);
    assert_eq!(c.next(0, &dim, 3, &all(&dim)), Vec::<u32>::new());
    // Five samples ranging 45 steps: 45 > 20·√5 = 44.7 passes, 44 does
    // not; the pixels beside a passing one go on at that level too.
    let mut five: Vec<Pixel> = (0..9).map(|_| pixel(50, 5, false)).collect();
    five[4].lo = [50; 3];
    five[4].hi = [95; 3];
    assert_eq!(c.next(1, &five, 3, &all(&five)), vec![1, 3, 4, 5, 7]);
    assert_eq!(c.next(2, &five, 3, &all(&five)), vec![4]);
    five[4].hi = [94; 3];
    assert_eq!(c.next(1, &five, 3, &all(&five)), Vec::<u32>::new());
    // Differing trees pass where trees are compared.
    let mut trees = five.clone();
    trees[0].trees_differ = true;
    let compared = Contrast {
        compare_trees: true,
        ..c
    };
    assert_eq!(compared.next(2, &trees, 3, &all(&trees)), vec![0]);
    // A bound past any range passes nothing, whatever its size: the
    // widest range, over the most samples, against 1, 1e300 and a
    // bound whose scaled square is 2⁶⁴ (it wrapped to 0 once).
    let mut widest: Vec<Pixel> = (0..9)
        .map(|_| pixel(0, Contrast::MAX_SAMPLES, false))
        .collect();
    widest[4].hi = [255; 3];
    let wraps = 2f64.powi(32) / (255.0 * f64::from(Contrast::RANGE_SCALE));
    for range in [1.0, 1e300, wraps] {
        let huge = Contrast {
            range: Some(range),
            ..c
        };
        for level in 0..3 {
            assert_eq!(
                huge.next(level, &widest, 3, &all(&widest)),
                Vec::<u32>::new()
            );
        }
    }
    // Just below the widest range over one sample, it passes.
    let just = Contrast {
        range: Some(254.0 / 255.0),
        ..c
    };
    let mut centres: Vec<Pixel> = (0..9).map(|_| pixel(0, 1, false)).collect();
    centres[4] = pixel(255, 1, false);
    assert_eq!(just.next(0, &centres, 3, &[4]), vec![4]);
}

/// Every pixel of `image`, as the pixels that reached a level.
fn all(image: &[Pixel]) -> Vec<u32> {
    (0..image.len() as u32).collect()
}

/// After the centres a pixel goes on where a neighbour of eight
/// differs from it; after the next level, one of four; after that,
/// only where its own samples differ.
#[test]
fn the_neighbours_a_pixel_looks_at_narrow_level_by_level() {
    let c = contrast(false);
    // A 3×3 image, the bottom-right pixel bright.
    let mut image: Vec<Pixel> = (0..9).map(|_| pixel(50, 1, false)).collect();
    image[8] = pixel(230, 1, false);
    assert_eq!(c.next(0, &image, 3, &all(&image)), vec![4, 5, 7, 8]);
    assert_eq!(c.next(1, &image, 3, &all(&image)), vec![5, 7, 8]);
    assert_eq!(c.next(2, &image, 3, &all(&image)), Vec::<u32>::new());
    // Only the pixels that reached the level are looked at.
    assert_eq!(c.next(0, &image, 3, &[0, 4, 8]), vec![4, 8]);
    // Differing trees send a pixel on where trees are compared.
    let mut trees = image.clone();
    trees[0].trees_differ = true;
    assert_eq!(c.next(2, &trees, 3, &all(&trees)), Vec::<u32>::new());
    assert_eq!(contrast(true).next(2, &trees, 3, &all(&trees)), vec![0]);
}
