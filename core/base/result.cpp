#include "core/base/result.h"

namespace cagewrap {

const char* error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::kFileNotFound: return "file not found";
    case ErrorCode::kFileUnreadable: return "file unreadable";
    case ErrorCode::kUnsupportedFormat: return "unsupported format";
    case ErrorCode::kParse: return "parse error";
    case ErrorCode::kEmpty: return "empty";
    case ErrorCode::kNonFinite: return "non-finite value";
    case ErrorCode::kIndexOutOfRange: return "index out of range";
    case ErrorCode::kTopologyMismatch: return "topology mismatch";
    case ErrorCode::kNoValidElements: return "no valid elements";
    case ErrorCode::kInvalidArgument: return "invalid argument";
    case ErrorCode::kVersion: return "unsupported version";
    case ErrorCode::kCancelled: return "cancelled";
    case ErrorCode::kWrite: return "write failed";
  }
  return "error";
}

}  // namespace cagewrap
