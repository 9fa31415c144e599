// The one exception type for bad input. Its message always names the file and,
// when there is one, the line: "scene.obj:12: reflectance Kd 1.2 is above 1".
#pragma once

#include <stdexcept>
#include <string>

namespace hrad {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, const std::string& what)
      : std::runtime_error(format(file, line, what)), file_(std::move(file)), line_(line) {}

  [[nodiscard]] const std::string& file() const { return file_; }
  /// 1-based line number, 0 when the error concerns the whole file.
  [[nodiscard]] int line() const { return line_; }

 private:
  static std::string format(const std::string& file, int line, const std::string& what) {
    return line > 0 ? file + ":" + std::to_string(line) + ": " + what : file + ": " + what;
  }
  std::string file_;
  int line_;
};

}  // namespace hrad
