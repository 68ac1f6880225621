// fdmsurf::Error as Python exceptions: fdmsurf.Error, one class per group of error codes (the
// CLI's exit codes) and one per code, each also a subclass of the matching builtin.
#include <array>
#include <exception>

#include "common.hpp"

namespace fdmsurf::python {
namespace {

// The classes live for the life of the process: references leaked on purpose, so that no
// Python object is destroyed by a C++ static destructor after the interpreter has finalised.
std::array<PyObject*, 9> by_code{};

PyObject* new_class(py::module_& m, const char* name, const char* doc, py::tuple bases,
                    const char* code) {
    py::dict namespace_;
    namespace_["code"] = code == nullptr ? py::object(py::none()) : py::object(py::str(code));
    namespace_["vk_result"] = 0;
    const std::string qualified = std::string("fdmsurf.") + name;
    PyObject* cls =
        PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), namespace_.ptr());
    if (cls == nullptr) throw py::error_already_set();
    m.add_object(name, py::handle(cls));  // the module holds one reference, `cls` another
    return cls;
}

}  // namespace

void bind_errors(py::module_& m) {
    auto tuple = [](std::initializer_list<PyObject*> types) {
        py::tuple t(types.size());
        std::size_t i = 0;
        for (PyObject* type : types) t[i++] = py::handle(type);
        return t;
    };
    PyObject* error = new_class(
        m, "Error",
        "Base class of every error fdmsurf raises; `code` names the library's ErrorCode "
        "('invalid-argument', 'io', 'format', 'empty-selection', 'no-device', 'device-limit', "
        "'vulkan', 'fft', 'internal'), `vk_result` holds the VkResult (or VkFFTResult) behind a "
        "Vulkan or FFT error, else 0. The message is the CLI's.",
        tuple({PyExc_Exception}), nullptr);
    PyObject* input = new_class(
        m, "InputError",
        "A structure or mesh that cannot be read (missing, malformed, nothing selected) or an "
        "output that cannot be written: the CLI's exit code 3.",
        tuple({error}), nullptr);
    PyObject* device =
        new_class(m, "DeviceError",
                  "No usable Vulkan device, a job too large for the device, or a Vulkan or VkFFT "
                  "failure: the CLI's exit code 4. On a machine without a GPU install "
                  "mesa-vulkan-drivers (lavapipe).",
                  tuple({error}), nullptr);
    using C = ErrorCode;
    by_code[static_cast<int>(C::InvalidArgument)] = new_class(
        m, "InvalidArgumentError",
        "An option or argument out of range or malformed (also a ValueError): the CLI's exit "
        "code 2.",
        tuple({error, PyExc_ValueError}), "invalid-argument");
    by_code[static_cast<int>(C::Io)] = new_class(
        m, "FileError", "A file that cannot be opened, read or written (also an OSError).",
        tuple({input, PyExc_OSError}), "io");
    by_code[static_cast<int>(C::Format)] = new_class(
        m, "FormatError", "Malformed, truncated or unrecognised input (also a ValueError).",
        tuple({input, PyExc_ValueError}), "format");
    by_code[static_cast<int>(C::EmptySelection)] =
        new_class(m, "EmptySelectionError", "No atoms left after selection (also a ValueError).",
                  tuple({input, PyExc_ValueError}), "empty-selection");
    by_code[static_cast<int>(C::NoDevice)] = new_class(
        m, "NoDeviceError", "No usable Vulkan device (the message says why for each one).",
        tuple({device}), "no-device");
    by_code[static_cast<int>(C::DeviceLimit)] =
        new_class(m, "DeviceLimitError", "The job does not fit the device's limits.",
                  tuple({device}), "device-limit");
    by_code[static_cast<int>(C::Vulkan)] =
        new_class(m, "VulkanError", "A Vulkan call failed (vk_result holds the VkResult).",
                  tuple({device}), "vulkan");
    by_code[static_cast<int>(C::Fft)] = new_class(
        m, "FftError", "VkFFT failed (vk_result holds the VkFFTResult).", tuple({device}), "fft");
    by_code[static_cast<int>(C::Internal)] =
        new_class(m, "InternalError", "A broken invariant: a bug in fdmsurf (please report it).",
                  tuple({error}), "internal");

    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const Error& e) {
            PyObject* cls = by_code[static_cast<std::size_t>(e.code())];
            // Messages name files, whose names need not be UTF-8.
            const std::string message = e.what();
            py::object text = py::reinterpret_steal<py::object>(
                PyUnicode_DecodeUTF8(message.data(), py::ssize_t(message.size()), "replace"));
            py::object instance = py::reinterpret_borrow<py::object>(cls)(text);
            if (e.vk_result() != 0) instance.attr("vk_result") = e.vk_result();
            PyErr_SetObject(cls, instance.ptr());
        }
    });
}

}  // namespace fdmsurf::python
