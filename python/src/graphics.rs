//! `Model.graphics`: the dataset's GRAPHICS statements ([`mbfx::session::graphics`]) as
//! `mbfx.Graphic` objects (a frozen dataclass of `python/mbfx/__init__.py`), their
//! kind's arguments in a dict by lower-case name; an argument the dataset leaves out is
//! None.

use mbfx::session::graphics::{Listed, Value};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};

/// A new list of `mbfx.Graphic`, one per statement of `listed`.
pub fn graphics<'py>(py: Python<'py>, listed: &[Listed]) -> PyResult<Bound<'py, PyList>> {
    static GRAPHIC: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let class = GRAPHIC.get_or_try_init(py, || {
        py.import("mbfx")?.getattr("Graphic").map(Bound::unbind)
    })?;
    let out = PyList::empty(py);
    for g in listed {
        let values = PyDict::new(py);
        for (name, v) in &g.values {
            values.set_item(name, value(py, v)?)?;
        }
        let kw = PyDict::new(py);
        kw.set_item("id", g.id)?;
        kw.set_item("kind", g.kind)?;
        kw.set_item("view_name", g.view_name.as_deref())?;
        kw.set_item("part", g.part)?;
        kw.set_item("markers", g.markers.clone())?;
        kw.set_item("values", values)?;
        out.append(class.bind(py).call((), Some(&kw))?)?;
    }
    Ok(out)
}

fn value<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Number(x) => x.into_pyobject(py)?.into_any(),
        Value::Integer(n) => n.into_pyobject(py)?.into_any(),
        Value::Ids(ids) => PyList::new(py, ids)?.into_any(),
        Value::Text(t) => t.into_pyobject(py)?.into_any(),
        Value::Absent => py.None().into_bound(py),
    })
}
