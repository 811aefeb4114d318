#include "cli/output_dir.h"

#include <fstream>
#include <system_error>
#include <unistd.h>

#include "core/error.h"

namespace fs = std::filesystem;

namespace cavesim::cli {

OutputDir::OutputDir(fs::path target, bool force) : target_(std::move(target)), force_(force) {
    std::error_code ec;
    if (fs::exists(target_, ec)) {
        if (!fs::is_directory(target_, ec))
            throw InputError("--out " + target_.string() + ": exists and is not a directory");
        if (!fs::is_empty(target_, ec) && !force_)
            throw InputError("--out " + target_.string() +
                             ": directory exists and is not empty; pass --force to replace it");
    }
}

OutputDir::~OutputDir() {
    if (!committed_ && !staging_.empty()) {
        std::error_code ec;
        fs::remove_all(staging_, ec);
    }
}

void OutputDir::open() {
    fs::path parent = target_.parent_path();
    if (parent.empty()) parent = ".";
    std::error_code ec;
    fs::create_directories(parent, ec);
    if (ec) throw RuntimeError("cannot create " + parent.string() + ": " + ec.message());
    staging_ = parent / ("." + target_.filename().string() + ".partial-" + std::to_string(::getpid()));
    fs::remove_all(staging_, ec);
    fs::create_directories(staging_, ec);
    if (ec) throw RuntimeError("cannot create " + staging_.string() + ": " + ec.message());
}

fs::path OutputDir::file(const std::string& relative) const {
    const fs::path p = staging_ / relative;
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    return p;
}

void OutputDir::commit() {
    std::error_code ec;
    fs::path old;
    if (fs::exists(target_, ec)) {
        old = target_.parent_path() / ("." + target_.filename().string() + ".old-" + std::to_string(::getpid()));
        if (target_.parent_path().empty()) old = "." + target_.filename().string() + ".old-" + std::to_string(::getpid());
        fs::rename(target_, old, ec);
        if (ec) throw RuntimeError("cannot move the old " + target_.string() + " aside: " + ec.message());
    }
    fs::rename(staging_, target_, ec);
    if (ec) {
        std::error_code ec2;
        if (!old.empty()) fs::rename(old, target_, ec2);
        throw RuntimeError("cannot move results into " + target_.string() + ": " + ec.message());
    }
    committed_ = true;
    if (!old.empty()) fs::remove_all(old, ec);
}

void writeTextFile(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw RuntimeError("cannot write " + path.string());
}

}  // namespace cavesim::cli
