#include "probe/json_input.h"

#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <vector>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/limits.h"

namespace probe {

using nlohmann::json;

namespace {

// What the library's parser leaves to its caller: the nesting depth, the number of values and keys
// that appear twice in one object, checked in a SAX pass (the DOM parser's callback form rescans an
// array each time an object in it ends, which is quadratic in the objects of one array). Throws
// ProbeError through `fail`; a syntax error is kept for the caller.
class JsonChecks final : public json::json_sax_t {
public:
    explicit JsonChecks(const std::function<ProbeError(const std::string&)>& fail) : fail_(fail) {}

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(json::number_integer_t) override { return value(); }
    bool number_unsigned(json::number_unsigned_t) override { return value(); }
    bool number_float(json::number_float_t, const json::string_t&) override { return value(); }
    bool string(json::string_t&) override { return value(); }
    bool binary(json::binary_t&) override { return value(); }
    bool start_object(std::size_t) override {
        value();
        enter();
        keys_.emplace_back();
        return true;
    }
    bool key(json::string_t& key) override {
        if (!keys_.back().insert(key).second) throw fail_(fmt::format("key '{}' appears twice in one object", key.substr(0, 64)));
        return true;
    }
    bool end_object() override {
        keys_.pop_back();
        --depth_;
        return true;
    }
    bool start_array(std::size_t) override {
        value();
        enter();
        return true;
    }
    bool end_array() override {
        --depth_;
        return true;
    }
    bool parse_error(std::size_t, const std::string&, const json::exception& e) override {
        // The library's message names the byte; a number too large for double is reported as such.
        error_ = e.what();
        if (const std::size_t colon = error_.find("] "); colon != std::string::npos) error_.erase(0, colon + 2);
        return false;
    }

    const std::string& error() const { return error_; }

private:
    // The document's tree takes some 100 bytes a value (an empty object's map included): the count
    // bounds it before it is built.
    bool value() {
        if (++values_ > kMaxJsonValues) throw fail_(fmt::format("holds more than {} values", kMaxJsonValues));
        return true;
    }
    void enter() {
        if (++depth_ > kMaxJsonDepth) throw fail_(fmt::format("nested deeper than {} levels", kMaxJsonDepth));
    }

    const std::function<ProbeError(const std::string&)>& fail_;
    int depth_ = 0;
    std::int64_t values_ = 0;
    std::vector<std::set<std::string>> keys_; // of each object open, innermost last
    std::string error_;
};

} // namespace

json parseJsonFile(std::string_view text, const std::filesystem::path& path, std::string_view what) {
    const std::function<ProbeError(const std::string&)> fail = [&](const std::string& problem) {
        return ProbeError(fmt::format("{}: {}: {}", path.string(), what, problem));
    };
    JsonChecks checks(fail);
    if (!json::sax_parse(text, &checks)) throw fail(fmt::format("not valid JSON, or incomplete ({})", checks.error().substr(0, 200)));
    return json::parse(text);
}

std::optional<int> jsonInt(const json& value) {
    if (value.is_number_unsigned()) {
        const auto v = value.get<json::number_unsigned_t>();
        if (v <= static_cast<json::number_unsigned_t>(std::numeric_limits<int>::max())) return static_cast<int>(v);
    } else if (value.is_number_integer()) {
        const auto v = value.get<json::number_integer_t>();
        if (v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max()) return static_cast<int>(v);
    }
    return std::nullopt;
}

std::string describeJson(const json& value) {
    if (value.is_structured()) return value.is_object() ? "an object" : "an array";
    std::string text = value.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return fmt::format("{} {}", value.type_name(), text);
}

} // namespace probe
