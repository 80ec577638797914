//! The search both modes' exact solves use when a bounce would put energy in (Newton's law at several simultaneous
//! contacts, or with friction on a turning body: Kane's paradox; a bounce begun a step's travel above the floor):
//! the largest scale of the contacts' restitution whose answer keeps the energy.

/// The answer at the largest restitution scale in [0, 1] whose energy is at most `limit`, given the full answer's
/// energy `full` (above the limit): by the secant method on the energy as a function of the scale (smooth while
/// restitution sets the bounce) from the full answer and the one at 0.98, in up to three more solves; if no scale
/// it tries keeps the energy, 0.9, 0.75, 0.5, 0.25 and the plastic answer (0), which is taken whatever its energy.
/// `solve(scale)` answers with the restitution scaled; `None` from it (no answer) ends the search with none.
pub(crate) fn largest_keeping_energy<T, E>(
    full: f64,
    limit: f64,
    mut solve: impl FnMut(f64) -> Result<Option<T>, E>,
    energy: impl Fn(&T) -> f64,
) -> Result<Option<T>, E> {
    let Some(at98) = solve(0.98)? else { return Ok(None) };
    let e98 = energy(&at98);
    let mut best = (e98 <= limit).then_some((0.98, at98));
    let (mut a, mut b) = ((0.98, e98), (1.0, full));
    for _ in 0..3 {
        if b.1 == a.1 {
            break;
        }
        let scale = (a.0 + (limit - a.1) * (b.0 - a.0) / (b.1 - a.1)).clamp(0.0, 1.0) * (1.0 - 1e-9);
        let Some(again) = solve(scale)? else { return Ok(None) };
        let e = energy(&again);
        if e <= limit && best.as_ref().is_none_or(|(s, _)| scale > *s) {
            best = Some((scale, again));
            if limit - e <= 1e-9 * limit.abs().max(1e-300) {
                break;
            }
        }
        (a, b) = (b, (scale, e));
    }
    if let Some((_, answer)) = best {
        return Ok(Some(answer));
    }
    for scale in [0.9, 0.75, 0.5, 0.25, 0.0] {
        let Some(again) = solve(scale)? else { return Ok(None) };
        if energy(&again) <= limit || scale == 0.0 {
            return Ok(Some(again));
        }
    }
    Ok(None)
}

/// The moving bodies that `contacts` touch, in order.
pub(crate) fn moving_bodies<'a>(
    states: &[tumble_contact::BodyState],
    contacts: impl IntoIterator<Item = &'a tumble_contact::Contact>,
) -> Vec<usize> {
    let mut members: Vec<usize> =
        contacts.into_iter().flat_map(|c| [c.a, c.b]).filter(|&k| states[k].is_dynamic()).collect();
    members.sort_unstable();
    members.dedup();
    members
}

/// The kinetic energy of the bodies `members` at velocities v (their inertia at the step's start).
pub(crate) fn kinetic(
    states: &[tumble_contact::BodyState],
    v: &[tumble_contact::BodyVelocity],
    members: &[usize],
) -> f64 {
    members.iter().map(|&k| body_kinetic(&states[k], &v[k])).sum()
}

/// One body's kinetic energy at velocity v (its inertia at the step's start).
pub(crate) fn body_kinetic(b: &tumble_contact::BodyState, v: &tumble_contact::BodyVelocity) -> f64 {
    0.5 * v.linear.norm_squared() / b.inv_mass + 0.5 * v.angular.dot(&(b.inertia * v.angular))
}

#[cfg(test)]
mod tests {
    use super::largest_keeping_energy;

    #[test]
    fn the_search_finds_the_largest_scale_that_keeps_the_energy() {
        // energy 1 + 2 (s - 0.5): the limit 1 is kept up to s = 0.5, which the secant finds from 0.98 and 1
        let mut tried = Vec::new();
        let found = largest_keeping_energy::<f64, ()>(
            2.0,
            1.0,
            |s| {
                tried.push(s);
                Ok(Some(s))
            },
            |s| 1.0 + 2.0 * (s - 0.5),
        )
        .unwrap()
        .unwrap();
        assert!((found - 0.5).abs() < 1e-8 && found <= 0.5, "{found}");
        assert_eq!(tried.len(), 2, "0.98, then the secant's exact root: {tried:?}");
        // no scale keeps it: the plastic answer
        let plastic = largest_keeping_energy::<f64, ()>(5.0, 1.0, |s| Ok(Some(s)), |_| 5.0).unwrap();
        assert_eq!(plastic, Some(0.0));
        // a failed solve ends the search with none
        assert_eq!(largest_keeping_energy::<f64, ()>(5.0, 1.0, |_| Ok(None), |_| 5.0).unwrap(), None);
    }
}
