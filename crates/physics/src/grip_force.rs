//! The minimum grip force of one state, by the cheapest way that gives the program's optimum:
//! in closed form or by the edge's reduced program (module `pivot`) where the part rests on its
//! edge, warm-started from the previous state of the rotation; the general conic program
//! ([`min_grip_force_conic`]) otherwise.

use crate::pivot::EdgeProblem;
use crate::polish::PrimalDual;
use crate::statics::{
    check_model, min_grip_force_conic, ContactModel, SolverError, StaticOutcome, StaticProblem,
    STICKY,
};

/// The smallest grip force that holds `problem` in equilibrium, or why none does: in closed
/// form where the part rests on its edge and the support's friction does not limit the grip,
/// else by the conic program — reduced to the edge's one balance equation where the part rests
/// on two contacts (module `pivot`), the general one ([`min_grip_force_conic`]) otherwise.
pub fn min_grip_force(
    problem: &StaticProblem,
    model: &ContactModel,
) -> Result<StaticOutcome, SolverError> {
    min_grip_force_from(problem, model, &mut WarmStart::default())
}

/// What one state's solution offers the next state of the same rotation: its optimum, from
/// which Newton's method reaches a neighbouring state's optimum in a few steps where the same
/// constraints are active (module `polish`; the result is checked to be an optimum, else the
/// interior-point solver runs). Whatever it holds, the answer is the program's optimum, to the
/// solvers' tolerance; only the time to it depends on the start.
#[derive(Clone, Debug, Default)]
pub struct WarmStart(Option<PrimalDual>);

/// [`min_grip_force`] started from a neighbouring state's `warm`, which it replaces with this
/// state's.
pub fn min_grip_force_from(
    problem: &StaticProblem,
    model: &ContactModel,
    warm: &mut WarmStart,
) -> Result<StaticOutcome, SolverError> {
    check_model(problem, model);
    let mu_s = model.mu_support;
    let edge = (mu_s > 0.0)
        .then(|| EdgeProblem::new(problem, model))
        .flatten();
    let Some(edge) = edge else {
        return min_grip_force_conic(problem, model);
    };
    let w = problem.weight;
    if let Some(eq) = edge.closed_form(w, mu_s) {
        return Ok(StaticOutcome::Held(eq));
    }
    // Where the interior-point solver stalls on the reduced program (its columns can be worse
    // scaled than the general program's), the general program decides.
    on_edge(&edge, w, mu_s, warm).or_else(|_| {
        warm.0 = None;
        min_grip_force_conic(problem, model)
    })
}

/// The reduced program of a part resting on its edge, started from `warm`.
fn on_edge(
    edge: &EdgeProblem,
    w: f64,
    mu_s: f64,
    warm: &mut WarmStart,
) -> Result<StaticOutcome, SolverError> {
    Ok(match edge.conic(w, mu_s, warm.0.as_ref())? {
        Some((eq, solution)) => {
            warm.0 = Some(solution);
            StaticOutcome::Held(eq)
        }
        // Would the support hold with (practically) unlimited friction?
        None => match edge.conic(w, STICKY, None)? {
            Some(_) => StaticOutcome::Slides,
            None => StaticOutcome::CannotHold,
        },
    })
}
