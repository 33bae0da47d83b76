// The Python module `motionfork`: the public C++ API (include/motionfork/motionfork.h) with NumPy
// arrays. It only converts types: arrays in and out, options as keyword arguments, C++ exceptions
// as Python ones (std::invalid_argument -> ValueError, a missing file or folder ->
// FileNotFoundError, the rest -> RuntimeError), the GIL released while C++ works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "motionfork/evaluate.h"
#include "motionfork/motionfork.h"

namespace py = pybind11;
namespace mf = motionfork;

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// FileNotFoundError naming `path` unless it exists (what: "model bundle folder", ...).
void RequireExists(const std::string& path, const char* what) {
  if (!std::filesystem::exists(path)) {
    PyErr_SetObject(PyExc_FileNotFoundError,
                    py::make_tuple(ENOENT, std::string(what) + " not found", path).ptr());
    throw py::error_already_set();
  }
}

// A float array (float32 or float64, any strides: copied when needed) as float32, C order.
FloatArray AsFloats(const py::handle& value, const char* name) {
  const py::array a = py::array::ensure(value);
  if (!a) {
    throw py::value_error(std::string(name) + ": expected a NumPy array of floats, got " +
                          std::string(py::str(py::type::of(value))));
  }
  if (a.dtype().kind() != 'f') {
    throw py::value_error(std::string(name) + ": expected a float32 or float64 array, got dtype " +
                          std::string(py::str(a.dtype())));
  }
  return FloatArray::ensure(a);
}

// The doubts among the API's notes on reading a motion ("warning: ...") as Python UserWarnings.
void WarnDoubts(const std::string& what, const std::vector<std::string>& notes) {
  const std::string prefix = "warning: ";
  for (const std::string& note : notes) {
    if (note.rfind(prefix, 0) != 0) continue;
    const std::string text = what + ": " + note.substr(prefix.size());
    if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 1) != 0) throw py::error_already_set();
  }
}

// Checks that `a` has `ndims` dimensions with the last two (joints, 3) = (J, 3).
void RequireShape(const FloatArray& a, std::vector<int> ndims, int joints, const char* name,
                  const char* layout) {
  bool ok = false;
  for (int n : ndims) ok = ok || a.ndim() == n;
  if (ok) ok = a.shape(a.ndim() - 1) == 3 && a.shape(a.ndim() - 2) == joints;
  if (!ok) {
    std::string shape = "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d)
      shape += (d ? ", " : "") + std::to_string(a.shape(d));
    throw py::value_error(std::string(name) + ": expected an array " + layout +
                          " with J = " + std::to_string(joints) + ", got shape " + shape +
                          (a.ndim() == 1 ? ",)" : ")"));
  }
}

std::vector<float> ToVector(const FloatArray& a, py::ssize_t offset, py::ssize_t count) {
  return std::vector<float>(a.data() + offset, a.data() + offset + count);
}

// A float32 array of `shape` holding `values`.
py::array_t<float> ToArray(const std::vector<float>& values, std::vector<py::ssize_t> shape) {
  py::array_t<float> out(shape);
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

py::ssize_t FramesOf(const std::vector<float>& values, size_t joints) {
  return static_cast<py::ssize_t>(values.size() / (3 * joints));
}

// A motion read from a file, with its skeleton (motionfork::MotionData).
struct PyMotion {
  mf::MotionData data;
  py::array_t<float> positions() const {
    return ToArray(data.positions,
                   {data.frames(), static_cast<py::ssize_t>(data.joint_names.size()), 3});
  }
};

mf::MotionData ToMotionData(const py::handle& motion, const py::object& joint_names,
                            const py::object& parents, double fps) {
  if (py::isinstance<PyMotion>(motion)) return motion.cast<PyMotion>().data;
  const FloatArray a = AsFloats(motion, "motion");
  if (a.ndim() != 3 || a.shape(2) != 3) {
    throw py::value_error("motion: expected a Motion or an array [T, J, 3], got " +
                          std::to_string(a.ndim()) + " dimensions");
  }
  mf::MotionData d;
  d.positions = ToVector(a, 0, a.size());
  const int J = static_cast<int>(a.shape(1));
  if (!joint_names.is_none()) {
    d.joint_names = joint_names.cast<std::vector<std::string>>();
  } else {
    for (int j = 0; j < J; ++j) d.joint_names.push_back("joint_" + std::to_string(j));
  }
  if (!parents.is_none()) {
    d.parents = parents.cast<std::vector<int>>();
  } else {  // a bare array: every joint hangs from the root (enough for .npy and .csv)
    d.parents.assign(J, 0);
    if (J > 0) d.parents[0] = -1;
  }
  if (static_cast<int>(d.joint_names.size()) != J) {
    throw py::value_error("joint_names: expected " + std::to_string(J) +
                          " names (the array's J), got " + std::to_string(d.joint_names.size()));
  }
  d.fps = fps;
  return d;
}

py::dict CheckDict(const mf::SampleCheck& c) {
  py::dict d;
  d["valid"] = c.valid;
  d["violating_frames"] = c.violating_frames;
  d["undefined_frames"] = c.undefined_frames;
  d["violated_constraints"] = c.violated_constraints;
  d["failed"] = c.failed;
  return d;
}

}  // namespace

PYBIND11_MODULE(motionfork, m) {
  m.doc() =
      "motionfork: diverse, controllable human motion prediction on the CPU.\n\n"
      "Load a model bundle, give it a history [T, J, 3] (metres, the model's joints), get K\n"
      "futures [K, T_his + T_pred, J, 3]; check them against the bundle's angle ranges and pose\n"
      "prior; read and write BVH, NumPy and CSV motions; fill missing joints (HG-VAE) and remove\n"
      "noise (Motion-DVAE). Same calls, same results as the `motionfork` command.";
  m.attr("__version__") = mf::Version();

  py::class_<PyMotion>(m, "Motion",
                       "A motion with its skeleton, as read_motion returns it. np.asarray(motion) "
                       "is its positions.")
      .def_property_readonly("positions", &PyMotion::positions,
                             "float32 [T, J, 3] metres; NaN where the file marks a value missing")
      .def_property_readonly(
          "joint_names", [](const PyMotion& p) { return p.data.joint_names; },
          "joint names, root first")
      .def_property_readonly(
          "parents", [](const PyMotion& p) { return p.data.parents; },
          "parent index per joint, -1 for the root")
      .def_property_readonly(
          "fps", [](const PyMotion& p) { return p.data.fps; }, "frame rate, Hz")
      .def(
          "__len__", [](const PyMotion& p) { return p.data.frames(); }, "frames")
      .def(
          "__array__",
          [](const PyMotion& p, py::object dtype, py::object copy) {
            py::array a = p.positions();
            return dtype.is_none() ? a : py::array(a.attr("astype")(dtype));
          },
          py::arg("dtype") = py::none(), py::arg("copy") = py::none())
      .def("__repr__", [](const PyMotion& p) {
        return "<motionfork.Motion " + std::to_string(p.data.frames()) + " frames, " +
               std::to_string(p.data.joint_names.size()) + " joints, " +
               std::string(py::str(py::float_(p.data.fps))) + " Hz>";
      });

  m.def(
      "read_motion",
      [](const std::string& path, const std::string& skeleton, double fps, double bvh_scale,
         const std::string& config_dir) {
        RequireExists(path, "motion file");
        mf::FileReadOptions o{skeleton, fps, bvh_scale, config_dir};
        py::gil_scoped_release release;
        return PyMotion{mf::ReadMotion(path, o)};
      },
      py::arg("path"), py::arg("skeleton") = "", py::arg("fps") = 0.0, py::arg("bvh_scale") = 0.01,
      py::arg("config_dir") = "",
      "Reads a .bvh, .npy or .csv motion file as a Motion (positions in metres, joint names,\n"
      "parents, fps). skeleton: a skeleton config name (e.g. 'bandai') or YAML path to put the\n"
      "motion on; fps: the frame rate of files that store none (.npy; default 30 Hz);\n"
      "bvh_scale: metres per BVH unit (0.01 = centimetres).");

  m.def(
      "write_motion",
      [](const std::string& path, const py::object& motion, py::object joint_names,
         py::object parents, double fps, double bvh_scale, const std::string& rotation_order) {
        const mf::MotionData d = ToMotionData(motion, joint_names, parents, fps);
        py::gil_scoped_release release;
        mf::WriteMotion(path, d, {bvh_scale, rotation_order});
      },
      py::arg("path"), py::arg("motion"), py::arg("joint_names") = py::none(),
      py::arg("parents") = py::none(), py::arg("fps") = 30.0, py::arg("bvh_scale") = 0.01,
      py::arg("rotation_order") = "ZXY",
      "Writes a Motion, or an array [T, J, 3] metres with joint_names / parents / fps, as .bvh\n"
      "(joint rotations fitted to the positions; needs parents), .npy or .csv, by the extension.\n"
      "All-or-nothing: a failed write leaves no file.");

  py::class_<mf::Model>(m, "Model",
                        "A trained forecasting model (a bundle folder such as models/bandai).")
      .def_static(
          "load",
          [](const std::string& path, const std::string& constraints, int threads,
             const std::string& config_dir, const std::string& joint_map, const std::string& unit,
             const std::string& up, const std::string& left_right, const std::string& precision) {
            RequireExists(path, "model bundle folder");
            mf::LoadOptions o{config_dir, constraints, threads,    joint_map,
                              unit,       up,          left_right, precision};
            py::gil_scoped_release release;
            return mf::Model::Load(path, o);
          },
          py::arg("path"), py::arg("constraints") = "", py::arg("threads") = 0,
          py::arg("config_dir") = "", py::arg("joint_map") = "", py::arg("unit") = "",
          py::arg("up") = "", py::arg("left_right") = "", py::arg("precision") = "auto",
          "Loads a model bundle. constraints: the angle-range set check() uses (a shipped name or\n"
          "a YAML path; '' = the bundle's own; 'none' = none); threads > 0 pins the thread pools\n"
          "(process-wide); joint_map: how motions of another rig map onto the model's joints\n"
          "('' = the rig convention their names follow; a convention name such as 'mixamo', or\n"
          "a joint map YAML, configs/rigs/README.md); unit ('m', 'cm', 'mm', 'in'), up ('y', 'z',\n"
          "'-z', ...) and left_right ('as-labelled', 'swapped') force how read_motion() and\n"
          "predict(Motion) read a motion's frame ('' = told from the body); precision: the\n"
          "generator's products, 'auto' (bf16 where the CPU has AVX512-BF16, else fp32), 'fp32'\n"
          "or 'bf16' (needs AVX512-BF16).")
      .def_property_readonly("joint_names", &mf::Model::joint_names, "joint names, root first")
      .def_property_readonly("parents", &mf::Model::parents,
                             "parent index per joint, -1 for the root")
      .def_property_readonly(
          "parts",
          [](const mf::Model& model) {
            py::dict d;
            for (const mf::Part& p : model.parts()) d[py::str(p.name)] = p.joints;
            return d;
          },
          "body parts in prediction order: name -> joints (the names fix= takes)")
      .def_property_readonly("fps", &mf::Model::fps, "frame rate, Hz")
      .def_property_readonly("history_frames", &mf::Model::history_frames,
                             "history frames predict() uses (the last ones given)")
      .def_property_readonly("future_frames", &mf::Model::future_frames, "frames of each future")
      .def_property_readonly("protocol", &mf::Model::protocol, "the protocol it was trained under")
      .def_property_readonly("constraint_set", &mf::Model::constraint_set,
                             "the angle-range set check() uses ('' for none)")
      .def_property_readonly("has_prior", &mf::Model::has_prior,
                             "whether the bundle carries a pose prior")
      .def(
          "predict",
          [](const mf::Model& model, const py::object& history, int k, uint64_t seed,
             std::vector<std::string> fix, bool repair) {
            const int J = static_cast<int>(model.joint_names().size());
            // One vector per history: a Motion's conformed frames moved in, an array's copied.
            std::vector<std::vector<float>> histories;
            bool batch = false;
            if (py::isinstance<PyMotion>(history)) {
              // [T, J, 3] on the model's joints by construction (Conform checks the rest).
              std::vector<std::string> notes;
              histories.push_back(model.Conform(history.cast<PyMotion>().data, &notes));
              WarnDoubts("motion", notes);
            } else {
              const FloatArray a = AsFloats(history, "history");
              RequireShape(a, {3, 4}, J, "history", "[T, J, 3] or [B, T, J, 3]");
              batch = a.ndim() == 4;
              const py::ssize_t n = batch ? a.shape(0) : 1;
              const py::ssize_t per = n == 0 ? 0 : a.size() / n;
              for (py::ssize_t b = 0; b < n; ++b) histories.push_back(ToVector(a, b * per, per));
            }
            const py::ssize_t B = static_cast<py::ssize_t>(histories.size());
            const mf::PredictOptions o{k, seed, std::move(fix), repair};
            const py::ssize_t frames = model.history_frames() + model.future_frames();
            const size_t history_values = static_cast<size_t>(model.history_frames()) * J * 3,
                         sample_values = static_cast<size_t>(frames) * J * 3;
            // The output written in place, each sample its history frames then its future.
            py::array_t<float> out =
                batch
                    ? py::array_t<float>(
                          {B, py::ssize_t{k}, frames, py::ssize_t{J}, py::ssize_t{3}})
                    : py::array_t<float>({py::ssize_t{k}, frames, py::ssize_t{J}, py::ssize_t{3}});
            float* dst = out.mutable_data();
            py::gil_scoped_release release;
            for (py::ssize_t b = 0; b < B; ++b) {
              const mf::Futures f = model.Predict(histories[b], o);
              const size_t future_values = sample_values - history_values;
              for (int i = 0; i < f.k; ++i) {
                float* s = dst + (static_cast<size_t>(b) * k + i) * sample_values;
                std::copy(f.history.begin(), f.history.end(), s);
                std::copy(f.sample(i), f.sample(i) + future_values, s + history_values);
              }
            }
            return out;
          },
          py::arg("history"), py::arg("k") = 50, py::arg("seed") = 0,
          py::arg("fix") = std::vector<std::string>{}, py::arg("repair") = true,
          "Samples k futures of a history: an array [T, J, 3] (metres, the model's joints,\n"
          "T >= history_frames; float32 or float64) or [B, T, J, 3] for B histories (each with\n"
          "the same seed), or a Motion from read_motion (mapped onto the model's joints by name\n"
          "and resampled). Returns float32 [k, history_frames + future_frames, J, 3] (or\n"
          "[B, k, ...]): the history the futures continue, then the future, as the command's\n"
          "prediction file. fix: parts whose latent code all futures share (e.g. ['legs']);\n"
          "repair: move poses outside the angle ranges back. Same seed, same futures.")
      .def(
          "check",
          [](const mf::Model& model, const py::object& motions) {
            const int J = static_cast<int>(model.joint_names().size());
            const FloatArray a = AsFloats(motions, "motions");
            RequireShape(a, {3, 4}, J, "motions", "[T, J, 3] or [K, T, J, 3]");
            const py::ssize_t K = a.ndim() == 4 ? a.shape(0) : 1,
                              per = a.size() / std::max<py::ssize_t>(K, 1);
            std::vector<mf::SampleCheck> checks;
            {
              std::vector<std::vector<float>> samples;
              for (py::ssize_t i = 0; i < K; ++i) samples.push_back(ToVector(a, i * per, per));
              py::gil_scoped_release release;
              for (const auto& s : samples) checks.push_back(model.CheckMotion(s));
            }
            py::list out;
            for (const mf::SampleCheck& c : checks) {
              py::dict d = CheckDict(c);
              d["nll"] = std::isnan(c.prior_nll) ? py::object(py::none())
                                                 : py::object(py::float_(c.prior_nll));
              out.append(d);
            }
            return out;
          },
          py::arg("motions"),
          "Checks motions against the angle ranges and, when the bundle has one, the pose prior:\n"
          "an array [K, T, J, 3] (e.g. predict()'s output, or futures[:, model.history_frames:]\n"
          "for the predicted frames only) or one [T, J, 3]. Returns a list with a dict per "
          "motion:\n"
          "valid, violating_frames, undefined_frames, violated_constraints (frames counted from\n"
          "the motion's first), nll (mean prior negative log-likelihood per pose, nats; None\n"
          "without a prior) and failed: the tests it fails ('angle_ranges', 'prior_nll': nll\n"
          "above prior_bound). valid: it fails none.")
      .def_property_readonly(
          "prior_bound",
          [](const mf::Model& model) -> py::object {
            const double b = model.prior_bound();
            return std::isnan(b) ? py::object(py::none()) : py::object(py::float_(b));
          },
          "the bound on a motion's mean prior NLL for check() to call it valid (the 99th\n"
          "percentile of real held-out poses); None without a prior")
      .def(
          "check_history",
          [](const mf::Model& model, const py::object& history) {
            const int J = static_cast<int>(model.joint_names().size());
            const FloatArray a = AsFloats(history, "history");
            RequireShape(a, {3}, J, "history", "[T, J, 3]");
            const std::vector<float> h = ToVector(a, 0, a.size());
            mf::HistoryDoubts c;
            {
              py::gil_scoped_release release;
              c = model.CheckHistory(h);
            }
            py::dict d;
            const auto number = [](double x) {
              return std::isnan(x) ? py::object(py::none()) : py::object(py::float_(x));
            };
            d["window_score"] = number(c.window_score);
            d["window_bound"] = number(c.window_bound);
            d["doubts"] = c.doubts;
            return d;
          },
          py::arg("history"),
          "The plausibility gate `motionfork predict` runs on a history [T, J, 3] (metres, the\n"
          "model's joints and frame; its last history_frames frames): a dict with doubts (a list\n"
          "of what is off, for people: 'scale: ...', 'axis: ...', 'left/right: ...', 'joint ...',\n"
          "'angle ranges: ...', 'prior: ...', 'HG-VAE: ...'; empty when it looks like what the\n"
          "model knows) and the HG-VAE window_score against its window_bound (None without an\n"
          "HG-VAE in the bundle).")
      .def(
          "read_motion",
          [](const mf::Model& model, const std::string& path) {
            RequireExists(path, "motion file");
            std::vector<float> p;
            std::vector<std::string> notes;
            {
              py::gil_scoped_release release;
              p = model.ReadMotion(path, &notes);
            }
            WarnDoubts(path, notes);
            const py::ssize_t J = static_cast<py::ssize_t>(model.joint_names().size());
            return ToArray(p, {FramesOf(p, J), J, 3});
          },
          py::arg("path"),
          "Reads a motion file onto the model's joints (by name, else by the roles of its rig's\n"
          "joints) and frame rate, in the model's frame (unit, up axis and left/right told from\n"
          "the body): float32 [T, J, 3], ready for predict(). Doubts about the input (upside\n"
          "down, left/right labels exchanged, no human size) are UserWarnings.");

  py::class_<mf::Prior>(m, "Prior", "A pose prior bundle (e.g. models/bandai/prior).")
      .def_static(
          "load",
          [](const std::string& path) {
            RequireExists(path, "prior bundle folder");
            py::gil_scoped_release release;
            return mf::Prior::Load(path);
          },
          py::arg("path"), "Loads a pose prior bundle folder.")
      .def_property_readonly("joint_names", &mf::Prior::joint_names, "joint names, root first")
      .def(
          "score",
          [](const mf::Prior& prior, const py::object& poses) {
            const int J = static_cast<int>(prior.joint_names().size());
            const FloatArray a = AsFloats(poses, "poses");
            RequireShape(a, {3}, J, "poses", "[T, J, 3]");
            std::vector<float> v = ToVector(a, 0, a.size());
            std::vector<double> nll;
            {
              py::gil_scoped_release release;
              nll = prior.Nll(v);
            }
            py::array_t<double> out(static_cast<py::ssize_t>(nll.size()));
            std::copy(nll.begin(), nll.end(), out.mutable_data());
            return out;
          },
          py::arg("poses"),
          "Negative log-likelihood of each pose, nats (lower = more plausible): poses [T, J, 3]\n"
          "metres on the prior's joints. Returns float64 [T].");

  py::class_<mf::Imputer>(m, "Imputer", "An HG-VAE bundle (e.g. models/bandai/hgvae).")
      .def_static(
          "load",
          [](const std::string& path) {
            RequireExists(path, "HG-VAE bundle folder");
            py::gil_scoped_release release;
            return mf::Imputer::Load(path);
          },
          py::arg("path"), "Loads an HG-VAE bundle folder.")
      .def_property_readonly("joint_names", &mf::Imputer::joint_names, "joint names, root first")
      .def_property_readonly("fps", &mf::Imputer::fps, "frame rate, Hz")
      .def(
          "impute",
          [](const mf::Imputer& imputer, const py::object& motion, const py::object& mask) {
            const int J = static_cast<int>(imputer.joint_names().size());
            const FloatArray a = AsFloats(motion, "motion");
            RequireShape(a, {3}, J, "motion", "[T, J, 3]");
            std::vector<float> v = ToVector(a, 0, a.size());
            if (!mask.is_none()) {
              const auto m =
                  py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(mask);
              if (!m || m.ndim() != a.ndim() || m.size() != a.size()) {
                throw py::value_error("mask: expected a boolean array of the motion's shape [T, " +
                                      std::to_string(J) + ", 3] (True = missing)");
              }
              for (py::ssize_t i = 0; i < m.size(); ++i)
                if (m.data()[i]) v[i] = std::numeric_limits<float>::quiet_NaN();
            }
            mf::Imputed r;
            {
              py::gil_scoped_release release;
              r = imputer.Impute(v);
            }
            return ToArray(r.positions, {a.shape(0), J, 3});
          },
          py::arg("motion"), py::arg("mask") = py::none(),
          "Fills the missing values of a motion [T, J, 3] (metres at fps on joint_names): NaN\n"
          "values, and those where mask (bool, same shape) is True. The root must be observed.\n"
          "Observed values come back exactly as given.");

  py::class_<mf::Denoiser>(m, "Denoiser", "A Motion-DVAE bundle (e.g. models/bandai/dvae).")
      .def_static(
          "load",
          [](const std::string& path) {
            RequireExists(path, "Motion-DVAE bundle folder");
            py::gil_scoped_release release;
            return mf::Denoiser::Load(path);
          },
          py::arg("path"), "Loads a Motion-DVAE bundle folder.")
      .def_property_readonly("joint_names", &mf::Denoiser::joint_names, "joint names, root first")
      .def_property_readonly("fps", &mf::Denoiser::fps, "frame rate, Hz")
      .def(
          "denoise",
          [](const mf::Denoiser& denoiser, const py::object& motion, const std::string& mode) {
            const int J = static_cast<int>(denoiser.joint_names().size());
            const FloatArray a = AsFloats(motion, "motion");
            RequireShape(a, {3}, J, "motion", "[T, J, 3]");
            std::vector<float> v = ToVector(a, 0, a.size()), out;
            {
              py::gil_scoped_release release;
              out = denoiser.Denoise(v, mode);
            }
            return ToArray(out, {a.shape(0), J, 3});
          },
          py::arg("motion"), py::arg("mode") = "",
          "Removes noise from a motion [T, J, 3] (metres at fps on joint_names, T >= 2): in the\n"
          "bundle's mode, or mode 'refiner', 'regression' or 'optimisation'. Deterministic.");

  m.def(
      "impute",
      [](const std::string& model_path, const py::object& motion, const py::object& mask) {
        RequireExists(model_path, "HG-VAE bundle folder");
        const mf::Imputer imputer = mf::Imputer::Load(model_path);
        return py::cast(&imputer, py::return_value_policy::reference).attr("impute")(motion, mask);
      },
      py::arg("model_path"), py::arg("motion"), py::arg("mask") = py::none(),
      "Imputer.load(model_path).impute(motion, mask).");
  m.def(
      "denoise",
      [](const std::string& model_path, const py::object& motion, const std::string& mode) {
        RequireExists(model_path, "Motion-DVAE bundle folder");
        const mf::Denoiser denoiser = mf::Denoiser::Load(model_path);
        return py::cast(&denoiser, py::return_value_policy::reference)
            .attr("denoise")(motion, mode);
      },
      py::arg("model_path"), py::arg("motion"), py::arg("mode") = "",
      "Denoiser.load(model_path).denoise(motion, mode).");

  m.def(
      "evaluate",
      [](const std::string& predictor, const std::string& protocol, const std::string& data, int k,
         uint64_t seed, const std::string& split, const std::string& subset,
         const std::string& clips, const std::string& fix, bool repair, int threads,
         const std::string& config_dir, const std::string& cache_dir) {
        mf::EvaluateOptions o;
        o.predictor = predictor;
        o.protocol = protocol;
        o.data = data;
        o.k = k;
        o.seed = seed;
        o.split_file = split;
        o.subset = subset;
        o.clips = clips;
        o.fix = fix;
        o.repair = repair;
        o.threads = threads;
        o.config_dir = config_dir;
        o.cache_dir = cache_dir;
        std::string json;
        {
          py::gil_scoped_release release;
          json = mf::EvaluateJson(o);
        }
        return py::module_::import("json").attr("loads")(json);
      },
      py::arg("predictor"), py::arg("protocol"), py::arg("data") = "", py::arg("k") = 50,
      py::arg("seed") = 0, py::arg("split") = "", py::arg("subset") = "test", py::arg("clips") = "",
      py::arg("fix") = "", py::arg("repair") = true, py::arg("threads") = 0,
      py::arg("config_dir") = "", py::arg("cache_dir") = "",
      "Evaluates a predictor (a model bundle folder, or 'zero-velocity' / 'constant-velocity' /\n"
      "'nearest-neighbours') on a protocol's test windows, as `motionfork eval` does: APD, ADE,\n"
      "FDE, MMADE, MMFDE (metres), overall and per action, the validity figures and where the\n"
      "body goes (the world root and foot skating), as a dict (the command's\n"
      "--json). data: the protocol's data folder; split: a split file; clips: a folder of\n"
      "motion files evaluated instead of data's test clips; fix: a part all samples share.");
}
