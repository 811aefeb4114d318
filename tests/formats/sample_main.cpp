// formats_sample DIR: writes every export of the hand-made cave of sample.h into DIR (created),
// for readers.py to load back with other programs' readers.
#include <cstdio>
#include <filesystem>

#include "formats/exports.h"
#include "sample.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: formats_sample DIR\n");
        return 2;
    }
    try {
        std::filesystem::create_directories(argv[1]);
        const cavesim::formats::test::Sample s = cavesim::formats::test::makeSample();
        cavesim::formats::ExportInputs in;
        in.domain = &s.domain;
        in.skeleton = &s.skeleton;
        in.stage2 = &s.stage2;  // the mesh is built from the domain
        for (const std::string& f :
             cavesim::formats::writeExports(in, argv[1], cavesim::formats::parseFormatSet("all")))
            std::printf("%s\n", f.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "formats_sample: %s\n", e.what());
        return 1;
    }
    return 0;
}
