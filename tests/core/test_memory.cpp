// The memory-limit parsers (core/memory.h) on file contents as the kernel writes them.
#include <map>

#include <gtest/gtest.h>

#include "core/memory.h"

using namespace cavesim;

TEST(Memory, MemAvailableFromMeminfo) {
    const std::string meminfo =
        "MemTotal:       24579412 kB\nMemFree:         1290388 kB\nMemAvailable:   21512996 kB\nBuffers: 10 kB\n";
    EXPECT_EQ(parseMemAvailable(meminfo), 21512996.0 * 1024);
    EXPECT_EQ(parseMemAvailable("MemTotal: 100 kB\n"), 0.0);
}

TEST(Memory, CgroupLimitFiles) {
    EXPECT_EQ(parseCgroupMemoryLimit("max\n"), 0.0);                  // v2, no limit
    EXPECT_EQ(parseCgroupMemoryLimit("6442450944\n"), 6442450944.0);  // v2, 6 GiB
    EXPECT_EQ(parseCgroupMemoryLimit("9223372036854771712\n"), 0.0);  // v1, no limit (2^63 − 4096)
    EXPECT_EQ(parseCgroupMemoryLimit("1073741824"), 1073741824.0);    // v1, 1 GiB, no newline
    EXPECT_EQ(parseCgroupMemoryLimit(""), 0.0);
    EXPECT_EQ(parseCgroupMemoryLimit("garbage"), 0.0);
}

TEST(Memory, ProcSelfCgroupV1AndV2) {
    const CgroupPaths v1 = parseProcCgroup("9:name=systemd:/\n4:memory:/process_api/a904\n3:cpuset:/\n0::/\n");
    EXPECT_TRUE(v1.hasV1);
    EXPECT_EQ(v1.v1, "/process_api/a904");
    EXPECT_TRUE(v1.hasV2);  // a hybrid hierarchy also lists the unified one
    EXPECT_EQ(v1.v2, "/");
    const CgroupPaths v2 = parseProcCgroup("0::/user.slice/user-1000.slice/session-2.scope\n");
    EXPECT_FALSE(v2.hasV1);
    EXPECT_EQ(v2.v2, "/user.slice/user-1000.slice/session-2.scope");
    const CgroupPaths both = parseProcCgroup("5:cpu,memory,pids:/box\n");
    EXPECT_EQ(both.v1, "/box");
}

TEST(Memory, CgroupLimitIsTheSmallestOnTheWayUp) {
    std::map<std::string, std::string> files = {
        {"/sys/fs/cgroup/memory.max", "max\n"},
        {"/sys/fs/cgroup/a/memory.max", "8000000000\n"},
        {"/sys/fs/cgroup/a/b/memory.max", "max\n"},
        {"/sys/fs/cgroup/a/b/c/memory.max", "9000000000\n"},
    };
    const auto read = [&](const std::string& path, std::string& text) {
        const auto it = files.find(path);
        if (it == files.end()) return false;
        text = it->second;
        return true;
    };
    EXPECT_EQ(cgroupLimitUpwards("/sys/fs/cgroup", "/a/b/c", "memory.max", read), 8e9);
    EXPECT_EQ(cgroupLimitUpwards("/sys/fs/cgroup", "/", "memory.max", read), 0.0);
    // A path the container cannot see: only the root's file is read.
    files["/sys/fs/cgroup/memory.max"] = "2000000000\n";
    EXPECT_EQ(cgroupLimitUpwards("/sys/fs/cgroup", "/hidden/x", "memory.max", read), 2e9);
}

TEST(Memory, UsableIsTheSmallestKnownLimit) {
    MemoryLimits m;
    EXPECT_EQ(m.usable(), 0.0);
    m.physical = 24e9;
    EXPECT_EQ(m.usable(), 24e9);
    m.available = 20e9;
    m.cgroup = 6e9;
    m.addressSpace = 8e9;
    EXPECT_EQ(m.usable(), 6e9);
    EXPECT_NE(m.describe().find("cgroup limit 6000 MB"), std::string::npos) << m.describe();
}
