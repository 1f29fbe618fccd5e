#include "pipeline/hdf5/error.h"

#include <H5Epublic.h>

#include <utility>

namespace fogpipe::hdf5 {
namespace {

std::string ComposeMessage(const std::string& file, const std::string& object,
                           const std::string& operation, const std::string& detail,
                           const std::string& stack) {
  std::string message = "HDF5 error in file '" + file + "'";
  if (!object.empty()) message += ", object '" + object + "'";
  message += ": " + operation + " failed";
  if (!detail.empty()) message += " (" + detail + ")";
  if (!stack.empty()) message += "\nHDF5 error stack:\n" + stack;
  return message;
}

std::string MessageText(hid_t message_id) {
  char buffer[256] = {0};
  if (H5Eget_msg(message_id, nullptr, buffer, sizeof(buffer)) < 0) return "?";
  return buffer;
}

herr_t AppendEntry(unsigned n, const H5E_error2_t* entry, void* client_data) {
  auto* text = static_cast<std::string*>(client_data);
  *text += "  #" + std::to_string(n) + " " + (entry->func_name ? entry->func_name : "?") +
           "(): " + (entry->desc ? entry->desc : "") + " [" + MessageText(entry->maj_num) + " / " +
           MessageText(entry->min_num) + "]\n";
  return 0;
}

}  // namespace

Error::Error(std::string file, std::string object, std::string operation, std::string detail,
             std::string hdf5_stack)
    : std::runtime_error(ComposeMessage(file, object, operation, detail, hdf5_stack)),
      file_(std::move(file)),
      object_(std::move(object)),
      operation_(std::move(operation)),
      hdf5_stack_(std::move(hdf5_stack)) {}

std::string Error::innermost_message() const {
  if (hdf5_stack_.empty()) return what();
  const size_t line_start = hdf5_stack_.rfind('\n');
  std::string line = hdf5_stack_.substr(line_start == std::string::npos ? 0 : line_start + 1);
  const size_t colon = line.find("): ");
  return colon == std::string::npos ? line : line.substr(colon + 3);
}

std::string CurrentErrorStack() {
  std::string text;
  // H5E_WALK_UPWARD starts at the innermost entry (the library routine that detected the error);
  // downward lists the API call first, which reads better from the top.
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, AppendEntry, &text);
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

}  // namespace fogpipe::hdf5
