//! The lines of a height field (its rows, or its columns as contiguous copies)
//! visited on every core with results that do not depend on the thread count:
//! the lines go to tasks of a fixed size and each task's result comes back in
//! order, for the caller to combine in that order.

use asperity_core::HeightField;
use rayon::prelude::*;

/// Lines per task. Columns are copied this many at a time into one buffer
/// (16 × 4096 samples is 512 KiB, within a core's L2 cache).
pub(crate) const LINES_PER_TASK: usize = 16;

/// Folds every line of `h` along x (each row) or, with `along_y`, along y (each
/// column) into a value started by `init`, one value per task of
/// [`LINES_PER_TASK`] lines, the tasks' values in order.
pub(crate) fn fold_lines<T: Send>(
    h: &HeightField,
    along_y: bool,
    init: impl Fn() -> T + Sync,
    fold: impl Fn(&mut T, &[f64]) + Sync,
) -> Vec<T> {
    let [nx, ny] = h.dims();
    let (n, lines) = if along_y { (ny, nx) } else { (nx, ny) };
    (0..lines.div_ceil(LINES_PER_TASK))
        .into_par_iter()
        .map_init(Vec::new, |strip, task| {
            let first = task * LINES_PER_TASK;
            let count = LINES_PER_TASK.min(lines - first);
            let mut value = init();
            if along_y {
                strip.clear();
                strip.resize(count * n, 0.0);
                for j in 0..ny {
                    for (c, &z) in h.row(j)[first..first + count].iter().enumerate() {
                        strip[c * n + j] = z;
                    }
                }
                strip.chunks_exact(n).for_each(|z| fold(&mut value, z));
            } else {
                (first..first + count).for_each(|j| fold(&mut value, h.row(j)));
            }
            value
        })
        .collect()
}

/// Folds the indices `0..len` into a value started by `init`, in tasks of
/// `per_task` consecutive indices, the tasks' values in order.
pub(crate) fn fold_range<T: Send>(
    len: usize,
    per_task: usize,
    init: impl Fn() -> T + Sync,
    fold: impl Fn(&mut T, std::ops::Range<usize>) + Sync,
) -> Vec<T> {
    let per_task = per_task.max(1);
    (0..len.div_ceil(per_task))
        .into_par_iter()
        .map(|task| {
            let mut value = init();
            fold(
                &mut value,
                task * per_task..((task + 1) * per_task).min(len),
            );
            value
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_line_once_in_order() {
        let (nx, ny) = (37, 53);
        let h = HeightField::from_vec([nx, ny], (0..nx * ny).map(|k| k as f64).collect()).unwrap();
        for along_y in [false, true] {
            let seen: Vec<Vec<f64>> = fold_lines(&h, along_y, Vec::new, |v, z| v.push(z[0] + z[1]))
                .into_iter()
                .flatten()
                .map(|s| vec![s])
                .collect();
            let expected: Vec<Vec<f64>> = if along_y {
                (0..nx).map(|i| vec![(2 * i + nx) as f64]).collect()
            } else {
                (0..ny).map(|j| vec![(2 * j * nx + 1) as f64]).collect()
            };
            assert_eq!(seen, expected, "along_y = {along_y}");
        }
    }
}
