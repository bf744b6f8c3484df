// load() and render() of the Python module (render_call.h): keyword arguments through the
// command line's parser, the render on its own thread, Ctrl-C and progress on Python's.
#include "python/render_call.h"

#include <Python.h>
#include <pybind11/numpy.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <set>
#include <thread>

#include "app/stats_json.h"
#include "scene/features.h"
#include "wavemmlt/error.h"

namespace wmlt::python {

namespace {

const std::set<std::string> kOptions = {"tracer",
                                        "spp",
                                        "time",
                                        "threads",
                                        "chains",
                                        "bootstrap",
                                        "pass_length",
                                        "p_large",
                                        "mis_beta",
                                        "seed",
                                        "width",
                                        "height",
                                        "max_length",
                                        "min_length",
                                        "mmlt_target",
                                        "mmlt_steps",
                                        "mmlt_target_exponent",
                                        "mmlt_delayed_rejection",
                                        "mmlt_film_steps",
                                        "spectral",
                                        "filter",
                                        "eye",
                                        "look_at",
                                        "up",
                                        "fov",
                                        "focus_distance",
                                        "f_stop"};

std::string valueText(const std::string& key, const py::handle& v) {
    if (py::isinstance<py::bool_>(v)) throw InputError("wavemmlt: " + key + "=" + std::string(py::str(v)) + ": not a value of " + key);
    if (py::isinstance<py::float_>(v)) return py::repr(v);
    if (py::isinstance<py::str>(v) || py::isinstance<py::int_>(v)) return py::str(v);
    if (py::isinstance<py::sequence>(v) && py::len(v) == 3) {  // eye, look_at, up
        std::string xyz;
        for (const py::handle& c : v) xyz += (xyz.empty() ? "" : ",") + valueText(key, c);
        return xyz;
    }
    // NumPy's scalars (np.arange's, say): an integer one as an int, a real one by repr.
    if (py::hasattr(v, "__index__")) return py::str(py::int_(py::reinterpret_borrow<py::object>(v)));
    if (py::hasattr(v, "__float__")) return py::repr(py::float_(py::reinterpret_borrow<py::object>(v)));
    throw InputError("wavemmlt: " + key + "=" + std::string(py::repr(v)) + ": not a value of " + key);
}

// The Python exception now set, as an object (and cleared).
py::object takeError() {
    PyObject *type, *value, *trace;
    PyErr_Fetch(&type, &value, &trace);
    PyErr_NormalizeException(&type, &value, &trace);
    if (trace) PyException_SetTraceback(value, trace);
    py::object e = py::reinterpret_steal<py::object>(value);
    Py_XDECREF(type);
    Py_XDECREF(trace);
    return e;
}

}  // namespace

bool isOptionKeyword(const std::string& key) { return kOptions.count(key) > 0; }
bool isCameraKeyword(const std::string& key) {
    return key == "eye" || key == "look_at" || key == "up" || key == "fov" || key == "focus_distance" || key == "f_stop";
}

std::vector<std::string> optionArguments(const py::dict& kwargs) {
    std::vector<std::string> args;
    for (const auto& [k, v] : kwargs) {
        const std::string key = py::str(k), flag = "--" + [&] {
            std::string f = key;
            for (char& c : f)
                if (c == '_') c = '-';
            return f;
        }();
        if (v.is_none()) continue;  // the scene's (or the default)
        if (key == "spectral") {
            if (!py::isinstance<py::bool_>(v)) throw InputError("wavemmlt: spectral=" + std::string(py::repr(v)) + ": True or False");
            args.push_back(v.cast<bool>() ? "--spectral" : "--rgb");
            continue;
        }
        args.push_back(flag);
        args.push_back(valueText(key, v));
    }
    return args;
}

CommandLine parseArguments(const std::vector<std::string>& args) {
    std::vector<std::string> all = {"wavemmlt"};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    return parseCommandLine(int(argv.size()), argv.data());
}

PyScene load(const py::object& path, const py::dict& kwargs) {
    PyScene s;
    py::dict options, camera;  // the camera is the scene's from now on (set_view changes it); the rest is render()'s
    for (const auto& [k, v] : kwargs) {
        const std::string key = py::str(k);
        if (isCameraKeyword(key)) camera[k] = v;
        else if (isOptionKeyword(key)) options[k] = v;
        else if (path.is_none())
            throw py::type_error("load() got an unexpected keyword argument '" + key + "' (the built-in scene has no <default>s)");
        else s.args.push_back("-D" + key + "=" + valueText(key, v));  // a Mitsuba <default>
    }
    for (const std::string& a : optionArguments(options)) s.args.push_back(a);
    if (!path.is_none()) s.path = py::str(py::module_::import("os").attr("fspath")(path));
    std::vector<std::string> args = s.args;
    if (!s.path.empty()) args.insert(args.begin(), s.path);
    for (const std::string& a : optionArguments(camera)) args.push_back(a);
    const CommandLine cl = parseArguments(args);
    {
        py::gil_scoped_release unlocked;  // (a large mesh takes a while; the dicts above are freed with the GIL held)
        s.desc = loadCommandLineScene(cl);
    }
    return s;
}

py::object imageArray(std::shared_ptr<Image> image) {
    auto* owner = new std::shared_ptr<Image>(image);
    py::capsule free(owner, [](void* p) { delete static_cast<std::shared_ptr<Image>*>(p); });
    const py::ssize_t w = image->width, h = image->height, f = sizeof(float);
    return py::array_t<float>({h, w, py::ssize_t(3)}, {w * 3 * f, 3 * f, f}, image->rgb.data(), free);
}

Image imageFromArray(const py::handle& array) {
    auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
    if (!a || a.ndim() != 3 || a.shape(2) != 3)
        throw InputError("wavemmlt: an image is an array of shape (height, width, 3), not " +
                         std::string(py::repr(py::getattr(array, "shape", py::none()))));
    Image im(int(a.shape(1)), int(a.shape(0)));
    std::copy(a.data(), a.data() + im.rgb.size(), im.rgb.begin());
    return im;
}

PyRender render(const PyScene& scene, const py::dict& kwargs) {
    py::dict options;
    py::object progress = py::none();
    bool lengthImages = false, strategyImages = false;
    for (const auto& [k, v] : kwargs) {
        const std::string key = py::str(k);
        if (key == "progress") progress = py::reinterpret_borrow<py::object>(v);
        else if (key == "length_images") lengthImages = v.cast<bool>();
        else if (key == "strategy_images") strategyImages = v.cast<bool>();
        else if (isOptionKeyword(key)) options[k] = v;
        else throw py::type_error("render() got an unexpected keyword argument '" + key + "'");
    }
    if (!progress.is_none() && !PyCallable_Check(progress.ptr())) throw py::type_error("render(): progress must be callable");
    std::vector<std::string> args = scene.args;
    if (!scene.path.empty()) args.insert(args.begin(), scene.path);  // (not loaded again: named for the options' rules)
    for (const std::string& a : optionArguments(options)) args.push_back(a);
    if (strategyImages) args.insert(args.end(), {"--strategy-images", "<strategy images>"});
    CommandLine cl = parseArguments(args);
    cl.defines.clear();  // (applied at load)

    SceneDesc desc = scene.desc;
    applyToScene(cl, desc);
    RenderOptions opt = renderOptionsFor(cl, desc.settings);
    if (cl.chains && *cl.chains > 0 && (desc.settings.tracer == TracerKind::MMLT || desc.settings.tracer == TracerKind::PSSMLT))
        checkChainMemory(*cl.chains, desc.settings, deriveFeatures(desc).media);
    opt.lengthImages = lengthImages;
    const Settings settings = desc.settings;

    std::atomic<bool> cancel{false}, done{false};
    std::atomic<double> fraction{-1};
    std::mutex m;
    std::condition_variable finished;
    std::vector<std::string> notices;
    opt.cancel = &cancel;
    opt.progress = [&](double f) { fraction = f; };
    opt.notice = [&](const std::string& n) {
        std::lock_guard<std::mutex> lock(m);
        notices.push_back(n);
    };
    RenderResult r;
    std::exception_ptr failure;
    py::object error;  // a Python exception raised while the render ran
    {
        py::gil_scoped_release unlocked;
        std::thread worker([&] {
            try {
                r = wmlt::render(std::move(desc), opt);
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(m);
            done = true;
            finished.notify_all();
        });
        double shown = -1;
        for (;;) {
            {
                std::unique_lock<std::mutex> lock(m);
                finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return done.load(); });
            }
            if (done) break;
            py::gil_scoped_acquire locked;
            if (!error && PyErr_CheckSignals() != 0) error = takeError();
            const double f = fraction;
            if (!error && !progress.is_none() && f >= 0 && f != shown) {
                shown = f;
                try {
                    progress(f);
                } catch (py::error_already_set& e) {
                    e.restore();
                    error = takeError();
                }
            }
            if (error) cancel = true;
        }
        worker.join();
    }
    if (failure) std::rethrow_exception(failure);

    PyRender out;
    out.image = std::make_shared<Image>(std::move(r.image));
    out.array = imageArray(out.image);
    out.stats = py::module_::import("json").attr("loads")(statsJson(r, settings));
    for (const std::string& n : notices) out.notices.append(n);
    for (const std::string& w : renderWarnings(r)) {
        out.warnings.append(w);
        if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
    }
    for (size_t k = size_t(opt.minPathLength); lengthImages && k < r.lengthImages.size(); ++k)
        out.lengthImages[py::int_(k)] = imageArray(std::make_shared<Image>(std::move(r.lengthImages[k])));
    for (StrategyImage& si : r.strategyImages)
        out.strategyImages[py::make_tuple(si.s, si.t)] = py::make_tuple(imageArray(std::make_shared<Image>(std::move(si.weighted))),
                                                                        imageArray(std::make_shared<Image>(std::move(si.unweighted))));
    if (error) {
        PyObject_SetAttrString(error.ptr(), "render", py::cast(std::move(out)).ptr());
        PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(error.ptr())), error.ptr());
        throw py::error_already_set();
    }
    return out;
}

}  // namespace wmlt::python
