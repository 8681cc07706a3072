//! What every section with a projectile checks of its runs' ends: the energy account closes,
//! and the crossed-triangle cells carry no pressure checkerboard that matters against the
//! metal's strength.

use crate::output::summary::Summary;
use crate::studies::sweep::RunRecord;

use super::report::Check;

/// The energy account's error at the end of a run, at most.
const ENERGY_TOLERANCE: f64 = 0.01;

/// A cell's pressure checkerboard at the end of a run, as a fraction of its flow stress, at
/// most (`summary.json`'s `checkerboard_over_flow_stress`).
const CHECKERBOARD_TOLERANCE: f64 = 0.10;

/// The two targets in words, for a section's text.
pub(super) fn targets() -> String {
    format!(
        "an energy error below {:.0} % and no cell's pressure checkerboard above {:.0} % of its \
         flow stress",
        100.0 * ENERGY_TOLERANCE,
        100.0 * CHECKERBOARD_TOLERANCE
    )
}

/// The two checks over `records` (`runs` names them in the report): not evaluated unless
/// every run completed, and the checkerboard's not where a run's build did not record it.
pub(super) fn checks(runs: &str, records: &[&RunRecord]) -> Vec<Check> {
    let done: Vec<(&str, &Summary)> = records
        .iter()
        .filter_map(|r| r.completed().map(|s| (r.label.as_str(), s)))
        .collect();
    let all_ran = !done.is_empty() && done.len() == records.len();
    let worst = |value: &dyn Fn(&Summary) -> Option<f64>| {
        done.iter()
            .map(|(label, s)| value(s).map(|v| (*label, v)))
            .collect::<Option<Vec<_>>>()
            .and_then(|all| all.into_iter().max_by(|a, b| a.1.total_cmp(&b.1)))
    };
    let check = |what: &str, tolerance: f64, worst: Option<(&str, f64)>, missing: &str| Check {
        what: format!("{what}, {runs}"),
        target: format!("below {:.0} %", 100.0 * tolerance),
        result: if all_ran {
            worst.map_or(missing.to_string(), |(label, v)| {
                format!("worst {:.2} % ({label})", 100.0 * v)
            })
        } else {
            "a run did not complete".to_string()
        },
        pass: worst.filter(|_| all_ran).map(|(_, v)| v < tolerance),
    };
    vec![
        check(
            "energy error at the end",
            ENERGY_TOLERANCE,
            worst(&|s| Some(s.energy_error.abs())),
            "–",
        ),
        check(
            "pressure checkerboard at the end against the cell's flow stress",
            CHECKERBOARD_TOLERANCE,
            worst(&|s| s.checkerboard_over_flow_stress),
            "not recorded by the runs' build",
        ),
    ]
}
