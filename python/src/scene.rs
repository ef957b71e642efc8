//! A scene of a mechanism in Python (`Mechanism.scene(name)`): the mechanism's sweep (its branch
//! rule and statuses) with the scene's solver at every row, as `mechgen sweep SCENE` runs it; the
//! columns of that command's CSV.

use mg::SceneDescription;
use mg::generic::Generic;
use mg::sweep::scene::scene_csv_header;
use pyo3::PyErr;
use pyo3::exceptions::{PyKeyError, PyValueError};

/// Which scene a `Mechanism` object runs, and what it computes.
#[derive(Clone)]
pub struct SceneFace {
    pub name: String,
    pub description: SceneDescription,
}

impl SceneFace {
    /// Scene `name` of `model`; `KeyError` naming the scenes it has.
    pub fn of(model: &Generic, name: &str) -> Result<SceneFace, PyErr> {
        let scene = model.scene(name).ok_or_else(|| {
            let names = model.scene_names();
            PyKeyError::new_err(match names.is_empty() {
                true => format!("`{}` has no scenes", model.name()),
                false => format!(
                    "`{}` has no scene `{name}` (its scenes: {})",
                    model.name(),
                    names.join(", ")
                ),
            })
        })?;
        Ok(SceneFace {
            name: name.to_string(),
            description: mg::DynScene::<f64>::info(&scene),
        })
    }

    /// The number columns of a sweep along input `input`: the input, the scene's outputs, `cond`.
    pub fn columns(&self, input: &str) -> Vec<String> {
        let mut h = scene_csv_header(&self.description, input);
        h.pop();
        h
    }

    /// What a method that runs whole mechanisms (`what`) says of this scene.
    pub fn refuse(&self, what: &str) -> PyErr {
        PyValueError::new_err(format!(
            "`{}` is a scene of `{}`: `sweep` and `batch` run it; {what} runs on the mechanism",
            self.name, self.description.mechanism
        ))
    }
}
