//! Array arguments: whatever the caller passed where the engine wants an array, read under the argument's name so
//! that a refusal says which argument was wrong and what was expected.
//!
//! Any real numeric dtype is taken where its meaning is clear: float and integer arrays where the engine wants
//! numbers (cast to float64), integer arrays where it wants indices (each value checked to fit), bool and integer
//! arrays where it wants flags. Lists and tuples are read as numpy reads them. Anything else (strings, objects,
//! complex numbers, None, the wrong number of dimensions or of columns) raises `InputError`, e.g. `points: expected
//! an (N, 2) array of numbers, got a string array of shape (5, 2)`. An array of the engine's own dtype is read in
//! place, without a copy.

use std::marker::PhantomData;

use crate::input_err;
use numpy::ndarray::Dimension;
use numpy::{
    Element, PyArray, PyArrayDescrMethods, PyArrayMethods, PyReadonlyArray, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

/// An array argument as the caller passed it: taking it never fails, reading it ([`ArrayArg::read`], or
/// [`ArrayArg::checked`] then [`Checked::read`]) checks it under the argument's name.
pub(crate) struct ArrayArg<'py>(Bound<'py, PyAny>);

impl<'a, 'py> FromPyObject<'a, 'py> for ArrayArg<'py> {
    type Error = std::convert::Infallible;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> Result<Self, Self::Error> {
        Ok(ArrayArg(obj.to_owned()))
    }
}

impl<'py> From<Bound<'py, PyAny>> for ArrayArg<'py> {
    /// An array nested in another argument (an item of a list, a value of a dict).
    fn from(obj: Bound<'py, PyAny>) -> Self {
        ArrayArg(obj)
    }
}

/// The element types the engine reads from arrays, with the numpy dtype kinds that may be cast to each.
pub(crate) trait Number: Element + Copy {
    /// What the array must hold, as the messages say it.
    const WHAT: &'static str;
    /// The smallest and largest value an integer must have to fit, when not every value of an accepted kind does.
    const RANGE: Option<(i64, i64)> = None;
    /// Whether an array of this dtype kind (numpy's `dtype.kind`: b'f', b'i', b'u', b'b', ...) means what the engine
    /// wants.
    fn accepts(kind: u8) -> bool;
}

impl Number for f64 {
    const WHAT: &'static str = "numbers";
    fn accepts(kind: u8) -> bool {
        matches!(kind, b'f' | b'i' | b'u')
    }
}

impl Number for i32 {
    const WHAT: &'static str = "integers";
    const RANGE: Option<(i64, i64)> = Some((i32::MIN as i64, i32::MAX as i64));
    fn accepts(kind: u8) -> bool {
        matches!(kind, b'i' | b'u')
    }
}

impl Number for u32 {
    const WHAT: &'static str = "integers";
    const RANGE: Option<(i64, i64)> = Some((0, u32::MAX as i64));
    fn accepts(kind: u8) -> bool {
        matches!(kind, b'i' | b'u')
    }
}

impl Number for bool {
    const WHAT: &'static str = "booleans";
    fn accepts(kind: u8) -> bool {
        matches!(kind, b'b' | b'i' | b'u')
    }
}

/// An array argument checked to hold values `T` can take, in as many dimensions as `D` and with an allowed number of
/// columns, but not yet cast: its shape can be checked against a limit before a cast copies it.
pub(crate) struct Checked<'py, T, D> {
    array: Bound<'py, PyUntypedArray>,
    name: String,
    expected: String,
    _element: PhantomData<(T, D)>,
}

impl<'py> ArrayArg<'py> {
    /// The array read as `T` in `D` dimensions; for two, `cols` lists the column counts allowed (empty: any).
    pub(crate) fn read<T: Number, D: Dimension>(
        &self,
        name: &str,
        cols: &[usize],
    ) -> PyResult<PyReadonlyArray<'py, T, D>> {
        self.checked::<T, D>(name, cols)?.read()
    }

    /// The array checked as [`ArrayArg::read`] checks it, not yet cast.
    pub(crate) fn checked<T: Number, D: Dimension>(
        &self,
        name: &str,
        cols: &[usize],
    ) -> PyResult<Checked<'py, T, D>> {
        let expected = expected::<T>(D::NDIM, cols);
        let refuse = |got: String| input_err(format!("{name}: expected {expected}, got {got}"));
        let obj = &self.0;
        if obj.is_none() {
            return Err(refuse("None".to_string()));
        }
        let (array, read_from) = match obj.cast::<PyUntypedArray>() {
            Ok(a) => (a.clone(), None),
            Err(_) => {
                let kind = type_name(obj);
                let array = obj
                    .py()
                    .import("numpy")?
                    .getattr("asarray")?
                    .call1((obj,))
                    .map_err(|e| {
                        refuse(format!("{} numpy cannot read as an array ({e})", a(&kind)))
                    })?
                    .cast_into::<PyUntypedArray>()
                    .map_err(|_| refuse(format!("{} numpy cannot read as an array", a(&kind))))?;
                (array, Some(kind))
            }
        };
        let got = || -> PyResult<String> {
            let described = format!(
                "{} array of shape {}",
                a(&dtype_name(&array)?),
                shape_text(array.shape())
            );
            Ok(match &read_from {
                None => described,
                Some(kind) => format!("{} read as {described}", a(kind)),
            })
        };
        if !T::accepts(array.dtype().kind()) || D::NDIM.is_some_and(|n| n != array.ndim()) {
            return Err(refuse(got()?));
        }
        if let (2, [_, c], false) = (array.ndim(), array.shape(), cols.is_empty()) {
            if !cols.contains(c) {
                // the message the engine has always given for a wrong column count
                return Err(input_err(format!(
                    "{name} must have shape {}, got (N, {c})",
                    shapes(cols)
                )));
            }
        }
        Ok(Checked {
            array,
            name: name.to_string(),
            expected,
            _element: PhantomData,
        })
    }
}

impl<'py, T: Number, D: Dimension> Checked<'py, T, D> {
    pub(crate) fn shape(&self) -> &[usize] {
        self.array.shape()
    }

    /// The array as `T`: in place when it already is, else cast (integers checked to fit first).
    pub(crate) fn read(self) -> PyResult<PyReadonlyArray<'py, T, D>> {
        let name = &self.name;
        let array = match self.array.cast::<PyArray<T, D>>() {
            Ok(same) => same.clone(),
            Err(_) => {
                if let Some((lo, hi)) = T::RANGE {
                    self.check_range(lo, hi)?;
                }
                let py = self.array.py();
                self.array
                    .call_method1("astype", (numpy::dtype::<T>(py),))?
                    .cast_into::<PyArray<T, D>>()
                    .map_err(|_| {
                        input_err(format!("{name}: could not be read as {}", self.expected))
                    })?
            }
        };
        array
            .try_readonly()
            .map_err(|e| input_err(format!("{name}: the array cannot be read ({e})")))
    }

    /// Refuses an integer array holding a value outside `lo..=hi`, naming the first extreme that is.
    fn check_range(&self, lo: i64, hi: i64) -> PyResult<()> {
        if self.array.len() == 0 {
            return Ok(());
        }
        for extreme in ["min", "max"] {
            let value = self.array.call_method0(extreme)?;
            let v: f64 = value.extract()?;
            if v < lo as f64 || v > hi as f64 {
                return Err(input_err(format!(
                    "{}: expected {} from {lo} to {hi}, got the value {value}",
                    self.name, self.expected
                )));
            }
        }
        Ok(())
    }
}

/// "an (N, 2) array of numbers", "an (N,) array of integers", "a 2-D array of numbers".
fn expected<T: Number>(ndim: Option<usize>, cols: &[usize]) -> String {
    let what = T::WHAT;
    match (ndim, cols) {
        (Some(1), _) => format!("an (N,) array of {what}"),
        (Some(2), []) => format!("a 2-D array of {what}"),
        (Some(2), cols) => format!("{} array of {what}", a(&shapes(cols))),
        (Some(n), _) => format!("a {n}-D array of {what}"),
        (None, _) => format!("an array of {what}"),
    }
}

/// "(N, 2)", "(N, 2) or (N, 3)".
fn shapes(cols: &[usize]) -> String {
    cols.iter()
        .map(|c| format!("(N, {c})"))
        .collect::<Vec<_>>()
        .join(" or ")
}

/// A shape as Python writes it: "(5, 3)", "(5,)", "()".
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The dtype as a user knows it: "float32", "int64", "bool", "string", "object".
fn dtype_name(array: &Bound<'_, PyUntypedArray>) -> PyResult<String> {
    let dtype = array.dtype();
    Ok(match dtype.kind() {
        b'U' => "string".to_string(),
        b'S' => "bytes".to_string(),
        b'O' => "object".to_string(),
        _ => dtype.str()?.to_string(),
    })
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "value".to_string())
}

/// `word` with its indefinite article: "a float32", "an int64", "a uint32", "an (N, 2)".
fn a(word: &str) -> String {
    let vowel = word
        .trim_start_matches('(')
        .starts_with(['a', 'e', 'i', 'o', 'N']);
    format!("{} {word}", if vowel { "an" } else { "a" })
}
