// hfts-quality REQUEST.json: prints the Ferrari-Canny epsilon of a grasp
// as JSON ({"epsilon": ...}); the request format is in
// docs/grasp_quality.md. "-" reads the request from standard input.
#include <fstream>
#include <iostream>
#include <sstream>

#include "grasp/grasp_quality.h"
#include "grasp/grasp_quality_json.h"

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::cerr << "usage: hfts-quality REQUEST.json   (or - for standard input)\n"
                 "Prints {\"epsilon\": ...}, the Ferrari-Canny L1 quality of the grasp.\n";
    return argc == 2 ? 0 : 2;
  }
  std::ostringstream text;
  if (std::string(argv[1]) == "-") {
    text << std::cin.rdbuf();
  } else {
    std::ifstream in(argv[1], std::ios::binary);
    if (!in) {
      std::cerr << "hfts-quality: cannot read '" << argv[1] << "'\n";
      return 1;
    }
    text << in.rdbuf();
  }
  try {
    const auto request = hfts::grasp::graspQualityRequestFromJson(text.str());
    std::cout << hfts::grasp::graspQualityResultToJson(hfts::grasp::graspQuality(request)) << "\n";
  } catch (const std::invalid_argument& e) {
    std::cerr << "hfts-quality: " << argv[1] << ": " << e.what() << "\n";
    return 2;
  }
  return 0;
}
