// Images the scene's materials look up (Cycles: scene/image.cpp); files are read by image_file.cpp.
#include <utility>

#include "scene.h"

namespace sphrect::render {

int RenderScene::AddImage(const std::string& name, int width, int height, int channels, const uint8_t* bytes,
                          const float* floats, bool srgb) {
    return AddImage(MakeImage(name, width, height, channels, bytes, floats, srgb));
}

int RenderScene::AddImage(Image image) {
    RequireNotCommitted();
    images.push_back(std::move(image));
    return int(images.size()) - 1;
}

}  // namespace sphrect::render
