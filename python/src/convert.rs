//! Problems: loading, building from Python data, overrides, and the conversions between Python
//! objects and TOML values.
//!
//! A [`Problem`] keeps the TOML text it was validated from, so every problem (from a file, a
//! dict or overrides) goes through the same parser and checks as a problem file given to the
//! CLI, and its messages are the CLI's. Overrides rebuild the text from the parsed table (the
//! comments go; the values round-trip exactly): line numbers in their messages refer to
//! [`Problem::to_toml`].
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use slither::problem;
use std::path::{Path, PathBuf};

/// A validated problem (the contents of a problem file).
#[pyclass(frozen, module = "slither_gait")]
pub struct Problem {
    /// The TOML text it was validated from.
    pub text: String,
    /// The file it came from (or a name such as `<dict>`), used in messages and the summary.
    pub path: PathBuf,
    /// The parsed problem.
    pub parsed: problem::Problem,
}

impl Problem {
    /// Parse and validate `text` named `path`, as the CLI does with a file.
    pub fn parse(text: String, path: PathBuf) -> PyResult<Self> {
        let parsed =
            problem::parse(&text, &path).map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Problem { text, path, parsed })
    }
}

/// A problem file's text, as the CLI reads it (messages name the file).
pub fn read_text(path: &Path) -> PyResult<String> {
    problem::read(path).map_err(|e| match e {
        problem::ProblemError::Io { .. } => pyo3::exceptions::PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    })
}

/// Read and validate a problem file (TOML, SI units).
#[pyfunction]
pub fn load_problem(path: PathBuf) -> PyResult<Problem> {
    let text = read_text(&path)?;
    Problem::parse(text, path)
}

#[pymethods]
impl Problem {
    /// A problem from nested dicts shaped like the file's tables, e.g.
    /// `{"rod": {"length": 1.0, ...}, "gait": {...}}`; `name` stands for the file in messages.
    #[staticmethod]
    #[pyo3(signature = (data, name = "<dict>"))]
    fn from_dict(data: &Bound<'_, PyDict>, name: &str) -> PyResult<Self> {
        let toml::Value::Table(t) = to_toml(data.as_any(), "")? else {
            unreachable!("a dict converts to a table")
        };
        Problem::parse(table_text(&t)?, PathBuf::from(name))
    }

    /// A problem from TOML text; `name` stands for the file in messages.
    #[staticmethod]
    #[pyo3(signature = (text, name = "<string>"))]
    fn from_toml(text: String, name: &str) -> PyResult<Self> {
        Problem::parse(text, PathBuf::from(name))
    }

    /// The TOML text of this problem (the file's own text when loaded from a file).
    fn to_toml(&self) -> String {
        self.text.clone()
    }

    /// The problem as nested dicts (the tables and keys written in its text; defaults are not
    /// filled in).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let t: toml::Table = toml::from_str(&self.text)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", self.path.display())))?;
        from_toml(py, &toml::Value::Table(t))
    }

    /// The file (or name) this problem came from.
    #[getter]
    fn path(&self) -> String {
        self.path.display().to_string()
    }

    /// A copy with some keys changed, validated as a file would be. Keys are dotted
    /// (`{"gait.speed": 0.3}`, or `with_(**{"gait.speed": 0.3})`) or tables given as dicts
    /// (`with_(gait={"speed": 0.3})`, merged into the table key by key).
    #[pyo3(signature = (overrides = None, **kwargs))]
    fn with_(
        &self,
        overrides: Option<&Bound<'_, PyDict>>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let mut t: toml::Table = toml::from_str(&self.text)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", self.path.display())))?;
        for d in [overrides, kwargs].into_iter().flatten() {
            for (k, v) in d.iter() {
                let key: String = k
                    .extract()
                    .map_err(|_| PyTypeError::new_err("override keys must be strings"))?;
                let value = to_toml(&v, &key)?;
                set_dotted(&mut t, &key, value)?;
            }
        }
        Problem::parse(table_text(&t)?, self.path.clone())
    }

    fn __repr__(&self) -> String {
        format!("Problem('{}')", self.path.display())
    }
}

/// TOML text of a table.
fn table_text(t: &toml::Table) -> PyResult<String> {
    toml::to_string(t).map_err(|e| PyValueError::new_err(format!("cannot write TOML: {e}")))
}

/// Set `key` (dotted: `gait.speed`) in `t` to `value`, creating tables on the way; a table
/// value is merged into an existing table key by key.
fn set_dotted(t: &mut toml::Table, key: &str, value: toml::Value) -> PyResult<()> {
    let mut parts: Vec<&str> = key.split('.').collect();
    let last = parts.pop().unwrap_or_default();
    if last.is_empty() || parts.iter().any(|p| p.is_empty()) {
        return Err(PyValueError::new_err(format!(
            "override `{key}`: a key is `table.key` or `table` (no empty parts)"
        )));
    }
    let mut here = t;
    for p in parts {
        let entry = here
            .entry(p.to_string())
            .or_insert_with(|| toml::Value::Table(Default::default()));
        here = match entry {
            toml::Value::Table(inner) => inner,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "override `{key}`: `{p}` is a value, not a table"
                )))
            }
        };
    }
    match (here.get_mut(last), value) {
        (Some(toml::Value::Table(old)), toml::Value::Table(new)) => {
            for (k, v) in new {
                set_dotted(old, &k, v)?;
            }
        }
        (_, value) => {
            here.insert(last.to_string(), value);
        }
    }
    Ok(())
}

/// A Python value as a TOML value (`key` names it in errors): bool, int, float, str, lists and
/// tuples, dicts with string keys, and anything with `tolist()` (numpy arrays and scalars).
pub fn to_toml(v: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if let Ok(s) = v.downcast::<PyString>() {
        return Ok(toml::Value::String(s.extract::<String>()?));
    }
    if let Ok(d) = v.downcast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, item) in d.iter() {
            let k: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!("`{key}`: table keys must be strings"))
            })?;
            let sub = if key.is_empty() {
                k.clone()
            } else {
                format!("{key}.{k}")
            };
            t.insert(k, to_toml(&item, &sub)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items = v
            .try_iter()?
            .map(|x| to_toml(&x?, key))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if v.hasattr("tolist")? {
        return to_toml(&v.call_method0("tolist")?, key);
    }
    Err(PyTypeError::new_err(format!(
        "`{key}`: cannot write a {} into a problem file (bool, int, float, str, list or dict)",
        v.get_type().name()?
    )))
}

/// A TOML value as a Python object (dates as strings).
pub fn from_toml<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(from_toml(py, x)?)?;
            }
            l.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, from_toml(py, x)?)?;
            }
            d.into_any()
        }
    })
}
