// The Python module `wavemmlt` (docs/python.md): load a scene of any of the three formats,
// render it with any tracer and every option the command line has, read the image as a
// NumPy array (no copy) and the --stats figures as a dict, and compare images as
// wavemmlt-img and the tests do.
//
//     import wavemmlt
//     scene = wavemmlt.load("cbox.xml", width=256, height=256)
//     r = scene.render(tracer="mmlt", spp=64, seed=1)
//     r.image            # float32 (256, 256, 3), linear RGB
//     r.stats["seconds"]
//     wavemmlt.diff(r.image, reference)["relmse"]
//
// Bad input raises wavemmlt.InputError (a ValueError) carrying file, line and problem.
#include <pybind11/eval.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "image/compare.h"
#include "python/render_call.h"
#include "scene/features.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"

namespace py = pybind11;
using namespace wmlt;
using namespace wmlt::python;

namespace {

const char* const kInputErrorPython = R"(
class InputError(ValueError):
    """Bad input (a scene, an image, an option's value): the message names the file and
    line, as the command line prints it; file ('' when the problem is not a file's), line
    (0: the whole file) and problem are its parts."""

    def __init__(self, message, file="", line=0, problem=""):
        super().__init__(message)
        self.file = file
        self.line = line
        self.problem = problem or message
)";

py::tuple vec(Vec3 v) { return py::make_tuple(v.x, v.y, v.z); }

py::dict cameraDict(const CameraDesc& c) {
    py::dict d;
    d["eye"] = vec(c.position);
    d["look_at"] = vec(c.lookAt);
    d["up"] = vec(c.up);
    d["fov"] = c.fovDegrees;
    d["focus_distance"] = c.focalLength;
    d["f_stop"] = c.dof ? c.fStop : 0.0f;
    return d;
}

// The camera's keywords through the command line's --eye ... --f-stop (their checks included).
void setView(PyScene& s, const py::dict& kwargs) {
    for (const auto& [k, v] : kwargs) {
        const std::string key = py::str(k);
        if (!isCameraKeyword(key)) throw py::type_error("set_view() got an unexpected keyword argument '" + key + "'");
    }
    applyCamera(parseArguments(optionArguments(kwargs)), s.desc.camera);
}

py::dict diffDict(const py::handle& a, const py::handle& b) {
    const ImageDiff d = diffImages(imageFromArray(a), imageFromArray(b));
    py::dict o;
    o["rmse"] = d.rmse;
    o["relmse"] = d.relmse;
    o["relmse_epsilon"] = kRelMseEpsilon;
    o["mae"] = d.mae;
    o["max_abs"] = d.maxAbs;
    o["nonfinite"] = d.nonFinite;
    return o;
}

// K runs of each side, their b x b block means per channel, compared by rstats::compareRuns.
py::dict compareBlocks(const py::list& runsA, const py::list& runsB, int block, double p) {
    if (py::len(runsA) < 2 || py::len(runsA) != py::len(runsB))
        throw InputError("wavemmlt: compare_blocks needs the same number (at least 2) of independent renders on each side");
    if (block < 1) throw InputError("wavemmlt: compare_blocks: block must be at least 1");
    auto stats = [&](const py::list& runs, int& w, int& h) {
        rstats::RunStats s;
        for (const py::handle& a : runs) {
            const Image im = imageFromArray(a);
            if (s.runs > 0 && (im.width != w || im.height != h)) throw InputError("wavemmlt: compare_blocks: the images differ in size");
            w = im.width;
            h = im.height;
            if (w < block || h < block) throw InputError("wavemmlt: compare_blocks: the image is smaller than a block");
            std::vector<double> v;
            for (int c = 0; c < 3; ++c)
                for (double x : rstats::blockMeans(im, block, c)) v.push_back(x);
            s.add(v);
        }
        return s;
    };
    int wa = 0, ha = 0, wb = 0, hb = 0;
    const rstats::RunStats a = stats(runsA, wa, ha), b = stats(runsB, wb, hb);
    if (wa != wb || ha != hb) throw InputError("wavemmlt: compare_blocks: the two sides' images differ in size");
    double ratio = 0;
    const rstats::ZTestResult z = rstats::compareRuns(a, b, p, &ratio);
    const int bw = wa / block, bh = ha / block;
    py::dict o;
    o["passed"] = z.pass;
    o["blocks"] = z.n;
    o["mean_z2"] = z.meanZ2;
    o["mean_z2_allowed"] = py::make_tuple(z.lowMeanZ2, z.highMeanZ2);
    o["mean_z"] = z.meanZ;
    o["mean_z_allowed"] = z.meanZBound;
    o["max_abs_z"] = z.maxAbsZ;
    o["max_abs_z_allowed"] = z.bonferroni;
    o["worst"] = py::dict(py::arg("x") = int(z.worst % size_t(bw * bh)) % bw * block, py::arg("y") = int(z.worst % size_t(bw * bh)) / bw * block,
                          py::arg("channel") = int(z.worst / size_t(bw * bh)), py::arg("a") = z.worstValue, py::arg("b") = z.worstExpected,
                          py::arg("se") = z.worstSe);
    o["mean_ratio"] = ratio;
    o["summary"] = z.describe();
    return o;
}

}  // namespace

PYBIND11_MODULE(wavemmlt, m) {
    m.doc() = "wavemmlt: a wavefront MMLT renderer (docs/python.md)";
    m.attr("__version__") = WAVEMMLT_VERSION;
    py::exec(kInputErrorPython, m.attr("__dict__"));
    // (A handle, kept for the process: a static py::object would be released after Python's end.)
    static py::handle inputError = py::object(m.attr("InputError")).release();
    py::register_exception_translator([](std::exception_ptr e) {
        try {
            if (e) std::rethrow_exception(e);
        } catch (const InputError& x) {
            py::object err = inputError(x.what(), x.file(), x.line(), x.problem());
            PyErr_SetObject(inputError.ptr(), err.ptr());
        }
    });

    py::class_<PyRender>(m, "Render", "A render's image and figures (Scene.render).")
        .def_readonly("image", &PyRender::array, "float32 array (height, width, 3), linear RGB; shares the render's memory")
        .def_readonly("stats", &PyRender::stats, "the figures --stats writes, as a dict")
        .def_readonly("warnings", &PyRender::warnings, "what the command line would print as warnings (also issued as Python warnings)")
        .def_readonly("notices", &PyRender::notices, "choices the render made (MMLT's chain count and why)")
        .def_readonly("length_images", &PyRender::lengthImages, "path length k -> its image (render(length_images=True); BPT, MMLT)")
        .def_readonly("strategy_images", &PyRender::strategyImages,
                      "(s, t) -> (weighted, unweighted) images of each BPT strategy (render(strategy_images=True))")
        .def(
            "write", [](const PyRender& r, const std::string& path, float exposure) { writeImage(path, *r.image, exposure); }, py::arg("path"),
            py::arg("exposure") = 0.0f, "write the image (.exr, .pfm, .png), to a temporary name then renamed");

    py::class_<PyScene>(m, "Scene", "A loaded scene (wavemmlt.load).")
        .def(
            "render", [](const PyScene& s, py::kwargs kw) { return render(s, kw); },
            "render(tracer=..., spp=..., time=..., seed=..., chains=..., threads=..., progress=callable(fraction), "
            "length_images=False, strategy_images=False, and any other option of the command line: width, height, "
            "max_length, min_length, p_large, bootstrap, pass_length, mis_beta, mmlt_target, mmlt_steps, mmlt_target_exponent, "
            "mmlt_delayed_rejection, mmlt_film_steps, spectral, "
            "filter, eye, look_at, up, fov, focus_distance, f_stop) -> Render. Ctrl-C stops the render at its next "
            "boundary and raises KeyboardInterrupt with the render so far as its .render")
        .def(
            "set_view", [](PyScene& s, py::kwargs kw) { setView(s, kw); },
            "set_view(eye=, look_at=, up=, fov=, focus_distance=, f_stop=): the camera for the next renders (as --eye ...)")
        .def_property_readonly("camera", [](const PyScene& s) { return cameraDict(s.desc.camera); })
        .def_property_readonly("path", [](const PyScene& s) { return s.path; })
        .def_property_readonly("width", [](const PyScene& s) { return s.desc.settings.width; })
        .def_property_readonly("height", [](const PyScene& s) { return s.desc.settings.height; })
        .def_property_readonly("tracer", [](const PyScene& s) { return std::string(tracerName(s.desc.settings.tracer)); })
        .def_property_readonly("max_length", [](const PyScene& s) { return s.desc.settings.maxPathLength; })
        .def_property_readonly("min_length", [](const PyScene& s) { return s.desc.settings.minPathLength; })
        .def_property_readonly("warnings", [](const PyScene& s) { return s.desc.warnings; })
        .def(
            "describe", [](const PyScene& s) { return deriveFeatures(s.desc).describe(); }, "the scene's feature set (--describe)");

    m.def(
        "load",
        [](py::object path, py::kwargs kw) {
            PyScene s = load(path, kw);
            for (const std::string& w : s.desc.warnings)
                if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
            return s;
        },
        py::arg("path") = py::none(),
        "load(path=None, **options) -> Scene: a thesis, Mitsuba 3 or pbrt-v4 file (None: the built-in scene). "
        "Keywords that are options of the command line override the file's settings (width=256, spp=64, "
        "tracer='bpt', ...); any other keyword sets a Mitsuba <default> (-D name=value). The scene's warnings are "
        "issued as Python warnings.");
    m.def(
        "read_image", [](const std::string& path) { return imageArray(std::make_shared<Image>(readImage(path))); }, py::arg("path"),
        "an image file (.exr .pfm .hdr: linear; .png .jpg: sRGB, linearised) as float32 (height, width, 3)");
    m.def(
        "write_image", [](const std::string& path, py::handle a, float exposure) { writeImage(path, imageFromArray(a), exposure); }, py::arg("path"),
        py::arg("image"), py::arg("exposure") = 0.0f, "write an array (height, width, 3) as .exr, .pfm or .png");
    m.def("diff", &diffDict, py::arg("image"), py::arg("reference"),
          "wavemmlt-img diff: rmse, relmse (epsilon 1e-2), mae, max_abs and nonfinite of an image against a reference");
    m.def(
        "relmse", [](py::handle a, py::handle b) { return diffImages(imageFromArray(a), imageFromArray(b)).relmse; }, py::arg("image"),
        py::arg("reference"), "mean((a - b)^2 / (b^2 + 1e-2)) over pixels and channels");
    m.def(
        "rmse", [](py::handle a, py::handle b) { return diffImages(imageFromArray(a), imageFromArray(b)).rmse; }, py::arg("image"),
        py::arg("reference"), "sqrt(mean((a - b)^2)) over pixels and channels");
    m.def("compare_blocks", &compareBlocks, py::arg("renders_a"), py::arg("renders_b"), py::arg("block") = 8, py::arg("p") = 1e-4,
          "the tests' comparison of two estimators: K independent renders each, their block means per channel, a z test "
          "of each block's difference with its measured standard error (sum z^2, max |z| and mean z, false-alarm "
          "probability p in all) -> dict with 'passed', the figures and the worst block");
}
