//! [`LogisticRegression::fit`]: Newton's method run to convergence, with a report.

use crate::newton::{FitReport, IterationLog, NewtonProblem, Termination};
use crate::{DesignRows, Features, LearningError, LogisticModel, LogisticRegression};

impl LogisticRegression {
    /// Fits the model on `x` (one row per sample) with labels `y` in `0..n_classes`.
    ///
    /// # Errors
    /// Invalid hyper-parameters, zero samples, a label count different from the sample
    /// count, a label `>= n_classes`, fewer than 2 classes, or a Hessian that cannot be
    /// factorised even with damping ([`LearningError::Singular`]). Not converging within
    /// `max_iter` is not an error: see [`FitReport::converged`].
    pub fn fit(
        &self,
        x: &Features<'_>,
        y: &[usize],
        n_classes: usize,
    ) -> Result<(LogisticModel, FitReport), LearningError> {
        self.fit_with_progress(x, y, n_classes, |_| {})
    }

    /// Like [`fit`](Self::fit), calling `progress` with the log of the starting point and of
    /// every Newton iteration as soon as it is done.
    ///
    /// # Errors
    /// As [`fit`](Self::fit).
    pub fn fit_with_progress(
        &self,
        x: &Features<'_>,
        y: &[usize],
        n_classes: usize,
        progress: impl FnMut(&IterationLog),
    ) -> Result<(LogisticModel, FitReport), LearningError> {
        self.fit_rows_with_progress(&DesignRows::plain(*x), y, n_classes, progress)
    }

    /// Like [`fit_with_progress`](Self::fit_with_progress) on rows read one at a time (for
    /// instance expanded as they are read, [`DesignRows::expanded`]): the same fit as on the
    /// rows stored whole, without holding them beside the solver's copy.
    ///
    /// # Errors
    /// As [`fit`](Self::fit).
    pub fn fit_rows_with_progress(
        &self,
        x: &DesignRows<'_>,
        y: &[usize],
        n_classes: usize,
        progress: impl FnMut(&IterationLog),
    ) -> Result<(LogisticModel, FitReport), LearningError> {
        let problem = NewtonProblem::from_rows(x, y, n_classes, self)?;
        self.solve_with_progress(problem, progress)
    }

    /// Runs Newton's method on a `problem` set up from this configuration
    /// ([`NewtonProblem::from_rows`] with `self`) to convergence, calling `progress` as
    /// [`fit_with_progress`](Self::fit_with_progress) does: the second half of
    /// [`fit_rows_with_progress`](Self::fit_rows_with_progress), for a caller that frees its
    /// rows once the problem holds its own copy of them.
    ///
    /// # Errors
    /// A Hessian that cannot be factorised even with damping ([`LearningError::Singular`]).
    pub fn solve_with_progress(
        &self,
        mut problem: NewtonProblem,
        mut progress: impl FnMut(&IterationLog),
    ) -> Result<(LogisticModel, FitReport), LearningError> {
        let threshold = self.gradient_tolerance * problem.n_samples() as f64;
        let start = problem.log(0.0, false, 0);
        progress(&start);
        let mut iterations = vec![start];
        let termination = loop {
            if problem.gradient_norm() <= threshold {
                break Termination::Converged;
            }
            if problem.iteration() >= self.max_iter {
                break Termination::MaxIterations;
            }
            let before = problem.objective();
            let log = problem.newton_step()?;
            progress(&log);
            // No decrease found, or a shortened step that left the objective unchanged: the
            // line search is deciding on rounding noise, and further iterations would only
            // repeat that (up to max_iter of them).
            let stalled = log.step == 0.0 || (log.step < 1.0 && log.objective >= before);
            iterations.push(log);
            if stalled {
                break Termination::NoProgress;
            }
        };
        let report = FitReport {
            iterations,
            converged: termination == Termination::Converged,
            termination,
        };
        Ok((problem.into_model(), report))
    }
}
