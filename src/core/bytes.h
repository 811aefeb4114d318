/// @file bytes.h
/// @brief Plain binary encoding of numbers and arrays into a byte string, and a reader that checks
/// every size before it uses it: the building blocks of the checkpoint of a run (app/checkpoint.h).
///
/// Values are written in the machine's byte order (little-endian on every platform cavesim builds
/// on); an array is its u64 element count followed by its elements' bytes. The reader never reads
/// past its end and never allocates more than the bytes left could hold: any inconsistency throws
/// InputError naming what was being read, so a damaged file is reported, never a crash.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"

namespace cavesim {

/// Appends values to a byte string.
class ByteWriter {
public:
    explicit ByteWriter(std::string& out) : out_(out) {}
    /// One trivially copyable value, its bytes as they are in memory.
    template <typename T>
    void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>, "ByteWriter::put needs a plain value");
        out_.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    /// An array: u64 count, then the elements.
    template <typename T>
    void putVector(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>, "ByteWriter::putVector needs plain elements");
        put(std::uint64_t(v.size()));
        out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
    /// A bit vector, one byte per entry.
    void putBools(const std::vector<bool>& v) {
        put(std::uint64_t(v.size()));
        for (bool b : v) out_.push_back(b ? '\1' : '\0');
    }
    void putString(const std::string& s) {
        put(std::uint64_t(s.size()));
        out_ += s;
    }

private:
    std::string& out_;
};

/// Reads what a ByteWriter wrote, checking every size against the bytes left.
class ByteReader {
public:
    /// `shown` names the source in messages ("out/.fig10.checkpoint/checkpoint.cavesim"); `what`
    /// says what a damaged source is not, and `advice` (if any) follows the reason.
    ByteReader(const char* data, std::size_t size, std::string shown,
               std::string what = "damaged or not a file this program wrote", std::string advice = "")
        : data_(data), size_(size), shown_(std::move(shown)), what_(std::move(what)), advice_(std::move(advice)) {}

    template <typename T>
    T get(const char* what) {
        static_assert(std::is_trivially_copyable_v<T>, "ByteReader::get needs a plain value");
        T v;
        std::memcpy(&v, take(sizeof v, what), sizeof v);
        return v;
    }
    /// An array written by putVector; its count must equal `expected` unless that is SIZE_MAX.
    template <typename T>
    void getVector(std::vector<T>& v, const char* what, std::size_t expected = std::size_t(-1)) {
        static_assert(std::is_trivially_copyable_v<T>, "ByteReader::getVector needs plain elements");
        const std::uint64_t n = get<std::uint64_t>(what);
        if (expected != std::size_t(-1) && n != expected)
            fail(std::string(what) + " of " + std::to_string(n) + " entries where " + std::to_string(expected) +
                 " belong");
        if (n > left() / sizeof(T)) fail(std::string("ends inside ") + what);
        v.resize(std::size_t(n));
        const char* from = take(std::size_t(n) * sizeof(T), what);
        if (n > 0) std::memcpy(v.data(), from, std::size_t(n) * sizeof(T));  // an empty vector's data() may be null
    }
    void getBools(std::vector<bool>& v, const char* what, std::size_t expected = std::size_t(-1)) {
        std::vector<std::uint8_t> bytes;
        getVector(bytes, what, expected);
        v.assign(bytes.size(), false);
        for (std::size_t i = 0; i < bytes.size(); ++i) {
            if (bytes[i] > 1) fail(std::string(what) + " holding a value other than 0 or 1");
            v[i] = bytes[i] != 0;
        }
    }
    std::string getString(const char* what) {
        const std::uint64_t n = get<std::uint64_t>(what);
        if (n > left()) fail(std::string("ends inside ") + what);
        return std::string(take(std::size_t(n), what), std::size_t(n));
    }
    const char* take(std::size_t n, const char* what) {
        if (n > left()) fail(std::string("ends inside ") + what);
        const char* p = data_ + at_;
        at_ += n;
        return p;
    }
    std::size_t left() const { return size_ - at_; }
    std::size_t at() const { return at_; }
    /// Throws InputError: `shown` is damaged or not a file this program wrote, and why.
    [[noreturn]] void fail(const std::string& why) const {
        throw InputError(shown_ + ": " + what_ + " (" + why + " at byte " + std::to_string(at_) + ")" + advice_);
    }

private:
    const char* data_;
    std::size_t size_, at_ = 0;
    std::string shown_, what_, advice_;
};

}  // namespace cavesim
