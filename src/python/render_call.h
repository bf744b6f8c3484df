// The Python module's scene and render (module.cpp binds them): keyword arguments become
// the command line's options and go through its parser (app/cli.h), so that a keyword
// means what its option means, is checked the same way, and a seed gives the image the
// command line gives.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "app/cli.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

namespace wmlt::python {

namespace py = pybind11;

// The options a keyword argument may name (load() and render() alike), as the command
// line spells them without "--" and with '_' for '-': "max_length" is --max-length.
bool isOptionKeyword(const std::string& key);
// The camera's among them (--eye, --look-at, --up, --fov, --focus-distance, --f-stop).
bool isCameraKeyword(const std::string& key);
// The command-line arguments of keyword arguments (True: the bare flag; spectral=False:
// --rgb; a 3-sequence: "X,Y,Z"; any other value: its str(), floats by repr so they
// round-trip). Throws InputError for a value an option cannot take.
std::vector<std::string> optionArguments(const py::dict& kwargs);
// parseCommandLine over "wavemmlt" and these arguments.
CommandLine parseArguments(const std::vector<std::string>& args);

// A loaded scene: the description with the load's options applied, and those options
// (without the camera's, which live in `desc`) for render() to start from.
struct PyScene {
    SceneDesc desc;
    std::string path;               // "" for the built-in scene
    std::vector<std::string> args;  // the load's options as command-line arguments
};

// A finished (or interrupted) render: the image and its figures.
struct PyRender {
    std::shared_ptr<Image> image;
    py::object array;  // `image` as a float32 (height, width, 3) array, no copy
    py::dict stats;    // --stats' keys
    py::list warnings, notices;
    py::dict lengthImages;    // k -> image (length_images=True)
    py::dict strategyImages;  // (s, t) -> (weighted, unweighted) (strategy_images=True, BPT)
};

// The array view of an image: it keeps the image alive and never copies it.
py::object imageArray(std::shared_ptr<Image> image);
// An image from an array of shape (height, width, 3) (any real dtype; copied).
Image imageFromArray(const py::handle& array);

PyScene load(const py::object& path, const py::dict& kwargs);
// Renders with the GIL released, on a thread of its own while this (Python's) thread
// polls every 50 ms for Ctrl-C and calls `progress`; on KeyboardInterrupt (or an
// exception from `progress`) the render stops at its next boundary and the exception is
// raised with the render so far as its `render` attribute.
PyRender render(const PyScene& scene, const py::dict& kwargs);

}  // namespace wmlt::python
