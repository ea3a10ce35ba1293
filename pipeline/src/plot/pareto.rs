//! Pareto fronts: the rows no other row dominates on a list of objectives, each minimised or
//! maximised. Row `a` dominates `b` when `a` is no worse than `b` in every objective and
//! better in at least one; rows equal in every objective do not dominate each other (both
//! stay on the front). A direct pairwise comparison: O(rows² objectives).

/// Whether an objective is minimised or maximised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    Min,
    Max,
}

/// One objective: a column and its direction (`gates_total:min`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Objective {
    pub column: String,
    pub direction: Direction,
}

impl Objective {
    /// Parse `COLUMN:min` or `COLUMN:max`.
    pub fn parse(s: &str) -> Result<Objective, String> {
        let (column, dir) = s.trim().rsplit_once(':').ok_or_else(|| {
            format!("{s:?}: expected COLUMN:min or COLUMN:max, e.g. gates_total:min")
        })?;
        let direction = match dir.trim() {
            "min" => Direction::Min,
            "max" => Direction::Max,
            d => {
                return Err(format!(
                    "{s:?}: unknown direction {d:?}: expected min or max"
                ))
            }
        };
        if column.trim().is_empty() {
            return Err(format!("{s:?}: expected a column before the ':'"));
        }
        Ok(Objective {
            column: column.trim().to_string(),
            direction,
        })
    }

    /// Parse a comma-separated list (`gates_total:min,total_psnr_db:max`).
    pub fn parse_list(s: &str) -> Result<Vec<Objective>, String> {
        s.split(',').map(Objective::parse).collect()
    }
}

/// Whether `a` dominates `b` (both one value per direction in `dirs`).
pub fn dominates(a: &[f64], b: &[f64], dirs: &[Direction]) -> bool {
    let mut better = false;
    for ((&x, &y), d) in a.iter().zip(b).zip(dirs) {
        let (x, y) = match d {
            Direction::Min => (x, y),
            Direction::Max => (-x, -y),
        };
        if x > y {
            return false;
        }
        if x < y {
            better = true;
        }
    }
    better
}

/// For each row, whether it is on the front (no other row dominates it).
pub fn front(rows: &[Vec<f64>], dirs: &[Direction]) -> Vec<bool> {
    rows.iter()
        .map(|r| !rows.iter().any(|o| dominates(o, r, dirs)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use Direction::{Max, Min};

    #[test]
    fn domination_needs_no_worse_everywhere_and_better_somewhere() {
        assert!(dominates(&[1.0, 5.0], &[2.0, 4.0], &[Min, Max]));
        assert!(!dominates(&[2.0, 4.0], &[1.0, 5.0], &[Min, Max]));
        // better in one, worse in the other: neither
        assert!(!dominates(&[1.0, 1.0], &[2.0, 0.0], &[Min, Min]));
        assert!(!dominates(&[2.0, 0.0], &[1.0, 1.0], &[Min, Min]));
        // equal: neither; equal in one and better in the other: yes
        assert!(!dominates(&[1.0, 1.0], &[1.0, 1.0], &[Min, Max]));
        assert!(dominates(&[1.0, 2.0], &[1.0, 1.0], &[Min, Max]));
        assert!(!dominates(&[1.0, 2.0], &[1.0, 1.0], &[Min, Min]));
    }

    #[test]
    fn a_known_front_with_ties_and_both_directions() {
        // (gates: min, psnr: max, cycles: min)
        let rows = vec![
            vec![100.0, 30.0, 10.0], // 0 front: cheapest
            vec![200.0, 40.0, 10.0], // 1 front: best psnr
            vec![200.0, 35.0, 10.0], // 2 dominated by 1
            vec![150.0, 30.0, 12.0], // 3 dominated by 0
            vec![200.0, 40.0, 10.0], // 4 ties 1: front too
            vec![300.0, 20.0, 5.0],  // 5 front: fewest cycles
        ];
        let f = front(&rows, &[Min, Max, Min]);
        assert_eq!(f, [true, true, false, false, true, true]);
        // on two objectives only, 5 falls (0 is cheaper and better)
        let two: Vec<Vec<f64>> = rows.iter().map(|r| r[..2].to_vec()).collect();
        assert_eq!(
            front(&two, &[Min, Max]),
            [true, true, false, false, true, false]
        );
        // flipping a direction flips the answer
        assert_eq!(
            front(&two, &[Max, Min]),
            [false, false, false, false, false, true]
        );
        assert_eq!(front(&[], &[Min]), Vec::<bool>::new());
    }

    #[test]
    fn objectives_parse_with_directions() {
        let o = Objective::parse_list("gates_total:min, total_psnr_db:max").unwrap();
        assert_eq!(o[0].column, "gates_total");
        assert_eq!(o[1].direction, Max);
        assert!(Objective::parse("gates_total:up")
            .unwrap_err()
            .contains("expected min or max"));
        assert!(Objective::parse("gates_total").is_err());
        assert!(Objective::parse(":min").is_err());
    }
}
