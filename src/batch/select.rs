//! Which cache a farm task runs: `--index N`, else the index a farm engine puts in the environment
//! of each task of an array (a Slurm job array, a Kubernetes Indexed Job), so the same command runs
//! the manifest as is, one cache per task.

use super::BatchError;

/// The variables read, in order: Slurm's job-array index, then Kubernetes' Indexed Job index.
pub const INDEX_VARIABLES: [&str; 2] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];

/// The index given by `flag`, else by the first of [`INDEX_VARIABLES`] that `env` holds; `None`
/// runs every cache.
pub fn task_index(
    flag: Option<usize>,
    env: impl Fn(&str) -> Option<String>,
) -> Result<Option<usize>, BatchError> {
    if flag.is_some() {
        return Ok(flag);
    }
    for name in INDEX_VARIABLES {
        if let Some(value) = env(name) {
            return value
                .trim()
                .parse()
                .map(Some)
                .map_err(|_| BatchError::IndexVariable { name, value });
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let pairs: Vec<(String, String)> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |name| {
            pairs
                .iter()
                .find(|(k, _)| k == name)
                .map(|(_, v)| v.clone())
        }
    }

    #[test]
    fn the_flag_then_slurm_then_kubernetes_choose() {
        assert_eq!(task_index(None, env(&[])).unwrap(), None);
        assert_eq!(
            task_index(Some(2), env(&[("SLURM_ARRAY_TASK_ID", "1")])).unwrap(),
            Some(2)
        );
        let both = env(&[("JOB_COMPLETION_INDEX", "3"), ("SLURM_ARRAY_TASK_ID", "1")]);
        assert_eq!(task_index(None, both).unwrap(), Some(1));
        assert_eq!(
            task_index(None, env(&[("JOB_COMPLETION_INDEX", "3")])).unwrap(),
            Some(3)
        );
    }

    #[test]
    fn a_value_that_is_no_index_is_refused_by_name() {
        let error = task_index(None, env(&[("SLURM_ARRAY_TASK_ID", "x1")])).unwrap_err();
        assert_eq!(
            error.to_string(),
            "SLURM_ARRAY_TASK_ID=x1 is not a cache index (0, 1, 2, …)"
        );
    }
}
