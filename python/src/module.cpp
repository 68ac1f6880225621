// The compiled half of the Python package fdmsurf (python/fdmsurf/__init__.py wraps it).
#include "common.hpp"
#include "fdmsurf/fdmsurf.hpp"

PYBIND11_MODULE(_fdmsurf, m) {
    m.doc() = "fdmsurf's compiled core; use the package fdmsurf, which wraps it.";
    m.attr("__version__") = fdmsurf::version();
    fdmsurf::python::bind_errors(m);
    fdmsurf::python::bind_options(m);
    fdmsurf::python::bind_structure(m);
    fdmsurf::python::bind_surface(m);
}
