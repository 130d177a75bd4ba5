// A connection in memory (HttpServer::ServeBytes, the HTTP fuzzer): reads
// from the input, writes to the output.
#pragma once

#include <httplib.h>

#include <cstring>
#include <string>
#include <string_view>

namespace surfdeform::http {

class MemoryStream final : public httplib::Stream {
 public:
  explicit MemoryStream(std::string_view input) : input_(input) {}
  bool is_readable() const override { return at_ < input_.size(); }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    const size_t n = std::min(size, input_.size() - at_);
    std::memcpy(ptr, input_.data() + at_, n);
    at_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    output_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 1;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 2;
  }
  socket_t socket() const override { return 0; }
  bool done() const { return at_ >= input_.size(); }
  std::string& output() { return output_; }

 private:
  std::string_view input_;
  size_t at_ = 0;
  std::string output_;
};

}  // namespace surfdeform::http
