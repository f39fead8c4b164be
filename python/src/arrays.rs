//! Columns as numpy arrays.

use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A dict builder whose values are numpy arrays.
pub struct Columns<'py> {
    np: Bound<'py, PyModule>,
    dict: Bound<'py, PyDict>,
}

impl<'py> Columns<'py> {
    pub fn new(py: Python<'py>) -> PyResult<Self> {
        Ok(Columns {
            np: py.import("numpy")?,
            dict: PyDict::new(py),
        })
    }

    /// `key`: a 1-D float64 array.
    pub fn f64(&self, key: &str, v: Vec<f64>) -> PyResult<()> {
        let a = self.np.call_method1("array", (v, "float64"))?;
        self.dict.set_item(key, a)
    }

    /// `key`: an N x 3 float64 array (also when N is 0).
    pub fn vec3(&self, key: &str, v: Vec<[f64; 3]>) -> PyResult<()> {
        let flat: Vec<f64> = v.iter().flatten().copied().collect();
        let a = self
            .np
            .call_method1("array", (flat, "float64"))?
            .call_method1("reshape", (-1, 3))?;
        self.dict.set_item(key, a)
    }

    /// `key`: a 1-D integer array of `dtype`.
    pub fn int<T: for<'a> IntoPyObject<'a>>(
        &self,
        key: &str,
        v: Vec<T>,
        dtype: &str,
    ) -> PyResult<()>
    where
        Vec<T>: for<'a> IntoPyObject<'a>,
    {
        let a = self.np.call_method1("array", (v, dtype))?;
        self.dict.set_item(key, a)
    }

    /// `key`: a 1-D array of strings.
    pub fn str(&self, key: &str, v: Vec<&str>) -> PyResult<()> {
        let a = self.np.call_method1("array", (v,))?;
        self.dict.set_item(key, a)
    }

    pub fn into_dict(self) -> Bound<'py, PyDict> {
        self.dict
    }
}
