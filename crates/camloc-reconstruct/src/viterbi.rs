//! The cheapest path through a trellis of per-step choices (Viterbi).

/// The choice at each step `t` (an index into `costs[t]`) that minimises the sum of the
/// chosen `costs[t][h]` plus `transition(t, from, to)` between consecutive steps (`from` a
/// choice of step `t - 1`, `to` one of step `t`). Steps without choices get index 0 and break
/// the path (no transition across them). Ties go to the lower index.
pub(crate) fn cheapest_path(
    costs: &[Vec<f64>],
    transition: impl Fn(usize, usize, usize) -> f64,
) -> Vec<usize> {
    let n = costs.len();
    let mut path = vec![0; n];
    // Back-pointers per step, and the running totals of the current run of steps.
    let mut back: Vec<Vec<usize>> = Vec::with_capacity(n);
    let mut total: Vec<f64> = Vec::new();
    let mut run_start = 0;
    let finish_run = |end: usize, total: &[f64], back: &[Vec<usize>], path: &mut [usize]| {
        if end == 0 || total.is_empty() {
            return;
        }
        let mut state = argmin(total);
        for t in (run_start_of(back, end)..end).rev() {
            path[t] = state;
            state = back[t].get(state).copied().unwrap_or(0);
        }
    };
    for (t, step) in costs.iter().enumerate() {
        if step.is_empty() {
            finish_run(t, &total, &back, &mut path);
            back.push(Vec::new());
            total.clear();
            run_start = t + 1;
            continue;
        }
        if t == run_start {
            total = step.clone();
            back.push(vec![0; step.len()]);
            continue;
        }
        let mut next = Vec::with_capacity(step.len());
        let mut pointers = Vec::with_capacity(step.len());
        for (to, cost) in step.iter().enumerate() {
            let (best, from) = total
                .iter()
                .enumerate()
                .map(|(from, sum)| (sum + transition(t, from, to), from))
                .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
            next.push(best + cost);
            pointers.push(from);
        }
        total = next;
        back.push(pointers);
    }
    finish_run(n, &total, &back, &mut path);
    path
}

/// The first step of the run of non-empty steps that ends just before `end`.
fn run_start_of(back: &[Vec<usize>], end: usize) -> usize {
    (0..end)
        .rev()
        .find(|&t| back[t].is_empty())
        .map_or(0, |t| t + 1)
}

/// Index of the smallest value (the first of equal ones; 0 for none or all NaN).
fn argmin(values: &[f64]) -> usize {
    values
        .iter()
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |best, (i, &v)| if v < best.1 { (i, v) } else { best },
        )
        .0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_pays_for_switching() {
        // Choice 1 is a little cheaper at step 2 alone, but switching costs more.
        let costs = vec![
            vec![0.0, 5.0],
            vec![0.0, 5.0],
            vec![1.0, 0.5],
            vec![0.0, 5.0],
        ];
        let switch = |_: usize, a: usize, b: usize| if a == b { 0.0 } else { 2.0 };
        assert_eq!(cheapest_path(&costs, switch), vec![0, 0, 0, 0]);
        // Without a price for switching, each step takes its own cheapest.
        assert_eq!(cheapest_path(&costs, |_, _, _| 0.0), vec![0, 0, 1, 0]);
        // A step without choices breaks the path; the runs are chosen apart.
        let broken = vec![vec![3.0, 0.0], vec![], vec![0.0, 3.0]];
        assert_eq!(cheapest_path(&broken, switch), vec![1, 0, 0]);
        assert!(cheapest_path(&[], switch).is_empty());
    }
}
