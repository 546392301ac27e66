//! How candidates are ranked for the plan file ("plans are ranked by score"): by S_rot, best
//! first, ties broken by the grip force the rotation needs; and when Algorithm 3 may stop.

use crate::axes::RotationAxisCandidate;
use crate::outcome::CandidateOutcome;

/// Whether `max_plans` plans are kept among the evaluated `outcomes` (ranked as the plan file
/// ranks them) and the worst of them scores above `next` by more than a tie: every candidate
/// from `next` on (sorted best first) ranks below them whatever it gives.
pub(crate) fn ranked_beyond(
    candidates: &[RotationAxisCandidate],
    outcomes: &[CandidateOutcome],
    max_plans: usize,
    next: f64,
) -> bool {
    if max_plans == 0 {
        return false;
    }
    let scores: Vec<f64> = candidates.iter().map(|c| c.score).collect();
    let kept: Vec<usize> = rank(&scores, |i| required_force(&outcomes[i]))
        .into_iter()
        .filter(|&i| matches!(&outcomes[i], CandidateOutcome::Planned { check: None, .. }))
        .take(max_plans)
        .collect();
    kept.len() == max_plans && kept.iter().all(|&i| scores[i] - next > SCORE_TIE)
}

/// Two scores closer than this are a tie, broken by the grip force the rotation needs.
const SCORE_TIE: f64 = 1e-9;

/// The order in which candidates are considered for the plan file: by S_rot (`scores`, sorted
/// best first), and within a run of tied scores by the grip force the rotation requires
/// (`force`, smaller first; infinite for a candidate without one), then by index.
pub(crate) fn rank(scores: &[f64], force: impl Fn(usize) -> f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..scores.len()).collect();
    let mut start = 0;
    while start < order.len() {
        let end = (start..scores.len())
            .find(|&j| (scores[j] - scores[start]).abs() > SCORE_TIE)
            .unwrap_or(scores.len());
        order[start..end].sort_by(|&a, &b| force(a).total_cmp(&force(b)).then(a.cmp(&b)));
        start = end;
    }
    order
}

/// The grip force (N) the plan of `outcome` requires, infinite when it has none.
pub(crate) fn required_force(outcome: &CandidateOutcome) -> f64 {
    match outcome {
        CandidateOutcome::Planned { physics, .. } => physics
            .as_ref()
            .and_then(|p| p.grip_force_required)
            .unwrap_or(f64::INFINITY),
        _ => f64::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::rank;

    #[test]
    fn ties_go_to_the_smaller_grip_force() {
        let scores = [3.0, 2.0, 2.0 + 1e-12, 2.0, 1.0, 1.0];
        let force = [50.0, 90.0, 20.0, f64::INFINITY, 5.0, 1.0];
        assert_eq!(rank(&scores, |i| force[i]), vec![0, 2, 1, 3, 5, 4]);
        // Distinct scores keep their order whatever the forces.
        let scores = [3.0, 2.0, 1.0];
        assert_eq!(rank(&scores, |i| [9.0, 5.0, 1.0][i]), vec![0, 1, 2]);
        assert!(rank(&[], |_| 0.0).is_empty());
    }
}
