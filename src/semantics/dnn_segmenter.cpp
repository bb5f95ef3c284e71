// OpenCV's headers stay in this file (DESIGN.md: heavy headers in single .cpp files).
#include "artemis/semantics/dnn_segmenter.hpp"
#include "artemis/io/read_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

namespace artemis::semantics {

namespace fs = std::filesystem;

namespace {

// The first line of an OpenCV error (the rest repeats file and function names).
std::string shortError(const cv::Exception& e) {
  std::string what = e.what();
  std::replace(what.begin(), what.end(), '\n', ' ');
  if (what.size() > 400) what = what.substr(0, 400) + "...";
  return what;
}

// Where the network's output lies relative to the image: the image was scaled to scaled_w x
// scaled_h, padded to the input size, and the output has out_w x out_h pixels for that input.
struct Geometry {
  int image_w = 0, image_h = 0;
  int scaled_w = 0, scaled_h = 0;
  int input_w = 0, input_h = 0;
  int out_w = 0, out_h = 0;
  // The output pixel that image pixel (u, v) reads (nearest).
  [[nodiscard]] std::size_t outputPixel(int u, int v) const {
    const double us = (u + 0.5) * scaled_w / image_w * out_w / input_w;
    const double vs = (v + 0.5) * scaled_h / image_h * out_h / input_h;
    const int uo = std::clamp(static_cast<int>(us), 0, out_w - 1);
    const int vo = std::clamp(static_cast<int>(vs), 0, out_h - 1);
    return static_cast<std::size_t>(vo) * static_cast<std::size_t>(out_w) + static_cast<std::size_t>(uo);
  }
};

int roundUp(int x, int multiple) {
  return (x + multiple - 1) / multiple * multiple;
}

}  // namespace

struct DnnSegmenter::Impl {
  cv::dnn::Net net;
  int net_w = 0;  // the input size `net` has run at (0: none yet)
  int net_h = 0;
  DenseModelConfig config;
  fs::path model;
  std::mutex mutex;  // one forward pass at a time

  // OpenCV 4.6's dnn computes wrong outputs once a network's input shape changes (measured with
  // the shared Torch ENet: a 1248x376 pass after a 256x128 one labelled every pixel Unlabeled,
  // while repeated passes at one size agree exactly), so a network runs at one input size only
  // and is loaded anew (about 60 ms) when the size changes.
  Status load();

  // Runs the network; `out` is its [1, labels, H, W] output.
  Status forward(const ImageU8& rgb, cv::Mat& out, Geometry& g);
  // The labels' probabilities at image pixel (u, v) into `p` (config.labels.size() values).
  void probabilities(const cv::Mat& out, const Geometry& g, int u, int v, float* p) const;
};

Status DnnSegmenter::Impl::load() {
  try {
    net = cv::dnn::readNet(model.string());
  } catch (const cv::Exception& e) {
    return parseError(fmt::format("{}: cannot load the network: {}", model.string(), shortError(e)));
  }
  if (net.empty()) return parseError(fmt::format("{}: cannot load the network (empty)", model.string()));
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  net_w = net_h = 0;
  return Status::ok();
}

Status DnnSegmenter::Impl::forward(const ImageU8& rgb, cv::Mat& out, Geometry& g) {
  if (rgb.empty() || rgb.channels() < 3) {
    return invalidArgument(fmt::format("the network needs an RGB image (got {} channels)", rgb.channels()));
  }
  const DenseModelInput& in = config.input;
  g.image_w = rgb.width();
  g.image_h = rgb.height();
  cv::Mat image(rgb.height(), rgb.width(), CV_8UC(rgb.channels()), const_cast<std::uint8_t*>(rgb.data().data()));
  if (in.resize_width > 0 && in.resize_width != rgb.width()) {
    g.scaled_w = in.resize_width;
    g.scaled_h =
        std::max(1, static_cast<int>(std::lround(static_cast<double>(rgb.height()) * in.resize_width / rgb.width())));
    cv::Mat scaled;
    cv::resize(image, scaled, cv::Size(g.scaled_w, g.scaled_h), 0, 0, cv::INTER_AREA);
    image = scaled;
  } else {
    g.scaled_w = rgb.width();
    g.scaled_h = rgb.height();
  }
  g.input_w = roundUp(g.scaled_w, in.size_multiple);
  g.input_h = roundUp(g.scaled_h, in.size_multiple);
  // NCHW, padded on the right and at the bottom with what a black pixel becomes.
  const int dims[] = {1, 3, g.input_h, g.input_w};
  cv::Mat blob(4, dims, CV_32F);
  const int channels = image.channels();
  for (int c = 0; c < 3; ++c) {
    const int source = in.bgr ? 2 - c : c;
    const auto mean = static_cast<float>(in.mean[static_cast<std::size_t>(c)]);
    const auto scale = static_cast<float>(in.scale);
    float* plane = blob.ptr<float>(0, c);
    std::fill(plane, plane + static_cast<std::size_t>(g.input_w) * static_cast<std::size_t>(g.input_h),
              (0.0f - mean) * scale);
    for (int v = 0; v < g.scaled_h; ++v) {
      const std::uint8_t* row = image.ptr<std::uint8_t>(v);
      float* dst = plane + static_cast<std::size_t>(v) * static_cast<std::size_t>(g.input_w);
      for (int u = 0; u < g.scaled_w; ++u) dst[u] = (static_cast<float>(row[u * channels + source]) - mean) * scale;
    }
  }
  if (net_w != 0 && (net_w != g.input_w || net_h != g.input_h)) {
    if (Status s = load(); !s.isOk()) return s;
  }
  net_w = g.input_w;
  net_h = g.input_h;
  try {
    net.setInput(blob);
    out = net.forward();
  } catch (const cv::Exception& e) {
    return invalidArgument(fmt::format("{}: the network rejects a {}x{} input (from a {}x{} image): {}", model.string(),
                                       g.input_w, g.input_h, g.image_w, g.image_h, shortError(e)));
  }
  const std::size_t labels = config.labels.size();
  if (out.dims != 4 || out.size[0] != 1 || out.type() != CV_32F) {
    return invalidArgument(
        fmt::format("{}: the network's output is not one [1, labels, height, width] float blob", model.string()));
  }
  if (static_cast<std::size_t>(out.size[1]) != labels) {
    return invalidArgument(fmt::format("{}: lists {} labels, but the network {} outputs {} channels", config.origin,
                                       labels, model.string(), out.size[1]));
  }
  g.out_h = out.size[2];
  g.out_w = out.size[3];
  return Status::ok();
}

void DnnSegmenter::Impl::probabilities(const cv::Mat& out, const Geometry& g, int u, int v, float* p) const {
  const std::size_t labels = config.labels.size();
  const std::size_t plane = static_cast<std::size_t>(g.out_w) * static_cast<std::size_t>(g.out_h);
  const auto* base = out.ptr<float>() + g.outputPixel(u, v);
  if (!config.output_scores) {
    float sum = 0.0f;
    for (std::size_t l = 0; l < labels; ++l) sum += (p[l] = std::max(0.0f, base[l * plane]));
    const float k = sum > 0.0f ? 1.0f / sum : 0.0f;
    for (std::size_t l = 0; l < labels; ++l) p[l] *= k;
    return;
  }
  float top = base[0];
  for (std::size_t l = 1; l < labels; ++l) top = std::max(top, base[l * plane]);
  float sum = 0.0f;
  for (std::size_t l = 0; l < labels; ++l) sum += (p[l] = std::exp(base[l * plane] - top));
  const float k = 1.0f / sum;
  for (std::size_t l = 0; l < labels; ++l) p[l] *= k;
}

DnnSegmenter::DnnSegmenter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
DnnSegmenter::~DnnSegmenter() = default;

const DenseModelConfig& DnnSegmenter::config() const {
  return impl_->config;
}

Result<std::unique_ptr<DnnSegmenter>> DnnSegmenter::open(const fs::path& model, DenseModelConfig config, int threads) {
  if (auto checked = io::checkInputFile(model, io::limits::kModel); !checked) return checked.status();
  auto impl = std::make_unique<Impl>();
  impl->config = std::move(config);
  impl->model = model;
  if (Status s = impl->load(); !s.isOk()) return s;
  cv::setNumThreads(std::max(1, threads));
  // One pass at the probe size: a network that cannot run, or a label count that disagrees with
  // its output, is found now rather than on every frame.
  const auto& probe = impl->config.input.probe_size;
  cv::Mat out;
  Geometry g;
  if (Status s = impl->forward(ImageU8(probe[0], probe[1], 3), out, g); !s.isOk()) {
    return Status(s.code(), fmt::format("{} (loading, with the probe size of {})", s.message(), impl->config.origin));
  }
  return std::unique_ptr<DnnSegmenter>(new DnnSegmenter(std::move(impl)));
}

Result<LabelProbabilities> DnnSegmenter::labelProbabilities(const ImageU8& rgb) {
  std::lock_guard lock(impl_->mutex);
  cv::Mat out;
  Geometry g;
  if (Status s = impl_->forward(rgb, out, g); !s.isOk()) return s;
  LabelProbabilities r;
  r.width = rgb.width();
  r.height = rgb.height();
  r.labels = impl_->config.labels.size();
  r.p.resize(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height) * r.labels);
  cv::parallel_for_(cv::Range(0, r.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      for (int u = 0; u < r.width; ++u) {
        impl_->probabilities(
            out, g, u, v,
            &r.p[(static_cast<std::size_t>(v) * static_cast<std::size_t>(r.width) + static_cast<std::size_t>(u)) *
                 r.labels]);
      }
    }
  });
  return r;
}

Result<SemanticObservation> DnnSegmenter::segment(const SegmentRequest& request, std::span<const ClassId> prompts) {
  SemanticObservation obs;
  if (request.view == nullptr || !request.view->hasImage()) {
    obs.note = "no image";
    return obs;
  }
  obs.observed = true;
  if (prompts.empty()) return obs;
  const ImageU8& rgb = request.view->image;
  std::lock_guard lock(impl_->mutex);
  cv::Mat out;
  Geometry g;
  if (Status s = impl_->forward(rgb, out, g); !s.isOk()) return s;
  const std::vector<ClassId> prompted(prompts.begin(), prompts.end());
  const LabelToPrompts gather(impl_->config, prompted);
  DenseProbabilities& dense = obs.dense;
  dense.width = rgb.width();
  dense.height = rgb.height();
  dense.classes.push_back(kNoClass);
  dense.classes.insert(dense.classes.end(), prompted.begin(), prompted.end());
  const std::size_t channels = dense.classes.size();
  dense.values.resize(static_cast<std::size_t>(dense.width) * static_cast<std::size_t>(dense.height) * channels);
  dense.top.resize(static_cast<std::size_t>(dense.width) * static_cast<std::size_t>(dense.height));
  const std::size_t labels = impl_->config.labels.size();
  cv::parallel_for_(cv::Range(0, dense.height), [&](const cv::Range& rows) {
    std::vector<float> label_p(labels);
    std::vector<float> channel_p(channels);
    for (int v = rows.start; v < rows.end; ++v) {
      std::uint8_t* dst = &dense.values[static_cast<std::size_t>(v) * static_cast<std::size_t>(dense.width) * channels];
      for (int u = 0; u < dense.width; ++u, dst += channels) {
        impl_->probabilities(out, g, u, v, label_p.data());
        gather.apply(label_p.data(), channel_p.data());
        std::size_t best = 0;
        for (std::size_t c = 0; c < channels; ++c) {
          dst[c] = static_cast<std::uint8_t>(std::lround(std::clamp(channel_p[c], 0.0f, 1.0f) * 255.0f));
          if (dst[c] > dst[best]) best = c;  // ties go to the lower channel, as argmax() does
        }
        dense.top[static_cast<std::size_t>(v) * static_cast<std::size_t>(dense.width) + static_cast<std::size_t>(u)] =
            static_cast<std::uint8_t>(best);
      }
    }
  });
  return obs;
}

std::vector<std::uint16_t> LabelProbabilities::argmax() const {
  std::vector<std::uint16_t> best(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0);
  for (std::size_t k = 0; k < best.size(); ++k) {
    const float* q = &p[k * labels];
    best[k] = static_cast<std::uint16_t>(std::max_element(q, q + labels) - q);
  }
  return best;
}

}  // namespace artemis::semantics
