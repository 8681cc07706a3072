//! Bisection for the speed at which a monotone yes/no outcome switches (the shell projectile's
//! critical velocity: below it no element fails, above it some do).

/// The final bracket: the outcome is no at `below` and yes at `above`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bracket {
    pub below: f64,
    pub above: f64,
}

impl Bracket {
    /// The bracket's midpoint, the best single estimate of the switch.
    pub fn mid(&self) -> f64 {
        0.5 * (self.below + self.above)
    }
}

/// How many evaluations [`bisect`] makes to shrink a bracket of `width` to `tol`.
pub fn steps(width: f64, tol: f64) -> usize {
    if width <= tol || tol <= 0.0 {
        0
    } else {
        (width / tol).log2().ceil() as usize
    }
}

/// Halves the bracket [`below`, `above`] (the caller has seen no at `below`, yes at `above`)
/// until it is no wider than `tol`, calling `test` at each midpoint. An error from `test`
/// stops the search.
pub fn bisect<E>(
    below: f64,
    above: f64,
    tol: f64,
    mut test: impl FnMut(f64) -> Result<bool, E>,
) -> Result<Bracket, E> {
    let mut b = Bracket { below, above };
    for _ in 0..steps(above - below, tol) {
        let mid = b.mid();
        if test(mid)? {
            b.above = mid;
        } else {
            b.below = mid;
        }
    }
    Ok(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A synthetic monotone outcome switching at 263.7: the bracket closes round it within the
    /// tolerance, with the predicted number of evaluations.
    #[test]
    fn bisection_brackets_the_switch_of_a_monotone_function() {
        let switch = 263.7;
        let mut calls = Vec::new();
        let b = bisect(200.0, 400.0, 5.0, |v| -> Result<bool, ()> {
            calls.push(v);
            Ok(v.powi(3) >= switch * switch * switch)
        })
        .unwrap();
        assert!(b.below < switch && switch <= b.above, "{b:?}");
        assert!(b.above - b.below <= 5.0);
        assert_eq!(calls.len(), steps(200.0, 5.0));
        assert_eq!(calls.len(), 6);
        assert_eq!(calls[0], 300.0);
        assert!((b.mid() - switch).abs() <= 2.5);
    }

    #[test]
    fn an_error_stops_the_search_and_a_narrow_bracket_needs_no_call() {
        let r = bisect(0.0, 1.0, 0.01, |_| Err::<bool, _>("no run"));
        assert_eq!(r, Err("no run"));
        let b = bisect(1.0, 1.5, 1.0, |_| -> Result<bool, ()> {
            panic!("not called")
        });
        assert_eq!(
            b,
            Ok(Bracket {
                below: 1.0,
                above: 1.5
            })
        );
    }
}
