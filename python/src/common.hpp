// Shared helpers of the Python module: numpy arrays over C++-owned memory, and the bindings'
// entry points, one per area (errors, structure, surface).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

#include "fdmsurf/error.hpp"

namespace fdmsurf::python {

namespace py = pybind11;

// A numpy array over `data` (which `owner` keeps alive), without a copy: the array's base is a
// capsule holding a reference to `owner`, so the memory lives as long as the array does, even
// after the Python object that handed it out is gone.
template <class T>
py::array share(const std::shared_ptr<void>& owner, T* data, std::vector<py::ssize_t> shape) {
    auto* hold = new std::shared_ptr<void>(owner);
    py::capsule base(hold, [](void* p) { delete static_cast<std::shared_ptr<void>*>(p); });
    return py::array_t<T>(std::move(shape), data, base);
}

// A file path from Python (str, bytes or os.PathLike) as the bytes the file system sees
// (os.fsencode: a str name that is not UTF-8 keeps its bytes). Raises TypeError for another
// type and ValueError for an embedded NUL, as open() does (the C++ side would cut the name short
// there and read or replace another file).
std::string path_argument(py::handle path);

// Text from C++ (messages, names read from files) as Python str: bytes that are not UTF-8
// (a file name's, a structure field's) become U+FFFD, as in error messages.
py::str text(const std::string& value);
py::list text_list(const std::vector<std::string>& values);

// The name of `value`'s type, for TypeError messages ("int").
std::string type_name(py::handle value);

// A numpy array of Python str (dtype '<U...'), for per-atom names, chains and elements.
py::array string_array(const std::vector<std::string>& values);

void bind_errors(py::module_& m);
void bind_structure(py::module_& m);
void bind_surface(py::module_& m);
void bind_options(py::module_& m);

}  // namespace fdmsurf::python
