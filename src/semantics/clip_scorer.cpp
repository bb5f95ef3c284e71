#include "artemis/semantics/clip_scorer.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "artemis/io/read_file.hpp"

namespace artemis::semantics {

namespace {

void normalise(std::vector<float>& v) {
  double n = 0.0;
  for (const float x : v) n += static_cast<double>(x) * x;
  n = std::sqrt(n);
  if (n > 0.0) {
    for (float& x : v) x = static_cast<float>(x / n);
  }
}

// The embeddings of an encoder's output: its first [batch, D] tensor, one row per item.
Result<std::vector<std::vector<float>>> rowsOf(const std::vector<onnx::Tensor>& outputs, std::size_t batch,
                                               const std::string& model) {
  for (const onnx::Tensor& t : outputs) {
    if (t.shape.size() != 2 || static_cast<std::size_t>(t.shape[0]) != batch || t.shape[1] <= 0) continue;
    const auto d = static_cast<std::size_t>(t.shape[1]);
    std::vector<std::vector<float>> rows(batch);
    for (std::size_t i = 0; i < batch; ++i) {
      rows[i].assign(t.values.begin() + static_cast<std::ptrdiff_t>(i * d),
                     t.values.begin() + static_cast<std::ptrdiff_t>((i + 1) * d));
      normalise(rows[i]);
    }
    return rows;
  }
  return invalidArgument(fmt::format("{}: no output of shape [{}, D] (the embedding)", model, batch));
}

Result<std::map<std::string, std::vector<float>>> readEmbeddings(const std::filesystem::path& path) {
  auto text = io::readTextFile(path, io::limits::kJson);
  if (!text) return Status(text.status().code(), text.status().message() + " (the text embeddings)");
  std::map<std::string, std::vector<float>> out;
  try {
    const auto j = nlohmann::json::parse(*text);
    if (!j.is_object()) return parseError(path.string() + ": text embeddings are an object: name -> [numbers]");
    std::size_t d = 0;
    for (const auto& [name, v] : j.items()) {
      if (!v.is_array() || v.empty() || !std::all_of(v.begin(), v.end(), [](const auto& x) { return x.is_number(); })) {
        return parseError(fmt::format("{}: '{}' is not a list of numbers", path.string(), name));
      }
      if (d != 0 && v.size() != d) {
        return parseError(fmt::format("{}: '{}' has {} numbers, the others {}", path.string(), name, v.size(), d));
      }
      d = v.size();
      std::vector<float> e;
      for (const auto& x : v) {
        const double value = x.template get<double>();
        if (!std::isfinite(value) || std::abs(value) > 1e30) {
          return parseError(fmt::format("{}: '{}' holds {}, not a usable number", path.string(), name, x.dump()));
        }
        e.push_back(static_cast<float>(value));
      }
      normalise(e);
      out.emplace(name, std::move(e));
    }
  } catch (const nlohmann::json::exception& e) {
    return parseError(fmt::format("{}: not valid JSON: {}", path.string(), e.what()));
  }
  return out;
}

// The model's only input, or an error naming the model.
Result<onnx::TensorInfo> onlyInput(const onnx::Session& s) {
  if (s.inputs().size() != 1) {
    return invalidArgument(fmt::format("{}: takes {} inputs; a CLIP encoder takes one", s.name(), s.inputs().size()));
  }
  return s.inputs().front();
}

}  // namespace

Result<std::unique_ptr<ClipScorer>> ClipScorer::open(const ClipConfig& config, const onnx::RuntimeOptions& runtime) {
  std::unique_ptr<ClipScorer> s(new ClipScorer());
  s->config_ = config;
  auto image = onnx::Session::open(config.image_model, runtime);
  if (!image) return image.status();
  s->image_ = std::move(*image);
  auto image_in = onlyInput(*s->image_);
  if (!image_in) return image_in.status();
  if (image_in->type != onnx::ElementType::kFloat || image_in->shape.size() != 4) {
    return invalidArgument(fmt::format("{}: its input is not a float image [batch, 3, h, w]", s->image_->name()));
  }
  if (!config.text_embeddings.empty()) {
    auto e = readEmbeddings(config.text_embeddings);
    if (!e) return e.status();
    s->precomputed_ = std::move(*e);
  }
  if (!config.text_model.empty()) {
    auto text = onnx::Session::open(config.text_model, runtime);
    if (!text) return text.status();
    s->text_ = std::move(*text);
    auto text_in = onlyInput(*s->text_);
    if (!text_in) return text_in.status();
    if (text_in->type != onnx::ElementType::kInt64 || text_in->shape.size() != 2) {
      return invalidArgument(fmt::format("{}: its input is not int64 token ids [1, context]", s->text_->name()));
    }
    auto tokenizer = ClipTokenizer::load(config.merges, config.max_merges);
    if (!tokenizer) return tokenizer.status();
    s->tokenizer_ = std::move(*tokenizer);
  }
  return s;
}

std::array<std::uint8_t, 3> ClipScorer::fillColour() const {
  // Image channel k feeds plane k, or plane 2 - k in BGR order; the plane's mean maps to zero.
  const NetworkInput& in = config_.image_input;
  std::array<std::uint8_t, 3> c{};
  for (std::size_t k = 0; k < 3; ++k) {
    const double v = in.mean[in.bgr ? 2 - k : k] / in.scale;
    c[k] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return c;
}

Result<std::vector<float>> ClipScorer::encodeText(const std::string& prompt) {
  const std::vector<std::int64_t> ids = tokenizer_->tokens(prompt, config_.context_length);
  onnx::Tensor in;
  in.type = onnx::ElementType::kInt64;
  in.shape = {1, static_cast<std::int64_t>(ids.size())};
  in.ints = ids;
  auto out = text_->run(std::span(&in, 1));
  if (!out) return out.status();
  auto rows = rowsOf(*out, 1, text_->name());
  if (!rows) return rows.status();
  return std::move(rows->front());
}

Result<std::vector<float>> ClipScorer::textEmbedding(const std::string& name) {
  if (const auto cached = cache_.find(name); cached != cache_.end()) return cached->second;
  std::string prompt = config_.prompt_template;
  const std::string shown = [&] {
    std::string s = name;
    std::replace(s.begin(), s.end(), '-', ' ');
    return s;
  }();
  prompt.replace(prompt.find("{}"), 2, shown);
  std::vector<float> e;
  if (const auto p = precomputed_.find(name); p != precomputed_.end()) {
    e = p->second;
  } else if (const auto q = precomputed_.find(prompt); q != precomputed_.end()) {
    e = q->second;
  } else if (text_ != nullptr) {
    auto encoded = encodeText(prompt);
    if (!encoded) return encoded.status();
    e = std::move(*encoded);
  } else {
    return notFound(fmt::format("{}: no embedding for '{}' or '{}', and no text_model to work one out",
                                config_.text_embeddings.string(), name, prompt));
  }
  cache_.emplace(name, e);
  return e;
}

Result<std::vector<std::vector<float>>> ClipScorer::imageEmbeddings(const std::vector<ImageU8>& crops) {
  std::vector<std::vector<float>> out;
  if (crops.empty()) return out;
  const onnx::TensorInfo& info = image_->inputs().front();
  NetworkInput input = config_.image_input;
  input.name = info.name;
  // Batches of up to kBatch crops where the encoder's first dimension is open, else one by one.
  constexpr std::size_t kBatch = 32;
  const std::size_t most = info.shape[0] < 0 ? kBatch : 1;
  onnx::Tensor one;
  for (std::size_t first = 0; first < crops.size(); first += most) {
    const std::size_t step = std::min(most, crops.size() - first);
    onnx::Tensor batch;
    batch.type = onnx::ElementType::kFloat;
    batch.shape = {static_cast<std::int64_t>(step), 3, input.height, input.width};
    for (std::size_t i = first; i < first + step; ++i) {
      fillInput(crops[i], input, one);
      batch.values.insert(batch.values.end(), one.values.begin(), one.values.end());
    }
    auto result = image_->run(std::span(&batch, 1));
    if (!result) return result.status();
    auto rows = rowsOf(*result, step, image_->name());
    if (!rows) return rows.status();
    for (auto& r : *rows) out.push_back(std::move(r));
  }
  return out;
}

Result<std::vector<std::vector<double>>> ClipScorer::classify(const std::vector<ImageU8>& crops,
                                                              const std::vector<std::string>& names) {
  std::vector<std::vector<float>> texts;
  for (const std::string& name : names) {
    auto e = textEmbedding(name);
    if (!e) return e.status();
    texts.push_back(std::move(*e));
  }
  for (const std::string& b : config_.background) {
    auto e = textEmbedding(b);
    if (!e) return e.status();
    texts.push_back(std::move(*e));
  }
  auto images = imageEmbeddings(crops);
  if (!images) return images.status();
  std::vector<std::vector<double>> out;
  for (const std::vector<float>& image : *images) {
    std::vector<double> logits;
    for (const std::vector<float>& text : texts) {
      if (text.size() != image.size()) {
        return invalidArgument(fmt::format("{}: image embeddings have {} numbers, text embeddings {}", image_->name(),
                                           image.size(), text.size()));
      }
      double cos = 0.0;
      for (std::size_t k = 0; k < text.size(); ++k) cos += static_cast<double>(text[k]) * image[k];
      logits.push_back(config_.temperature * cos);
    }
    const double top = *std::max_element(logits.begin(), logits.end());
    double sum = 0.0;
    for (double& l : logits) sum += (l = std::exp(l - top));
    for (double& l : logits) l /= sum;
    out.push_back(std::move(logits));
  }
  return out;
}

}  // namespace artemis::semantics
