// Images the scene's materials look up (Cycles: scene/image.cpp); files are read by image_file.cpp.
#include <utility>

#include "options.h"
#include "scene.h"

namespace sphrect::render {

int RenderScene::AddImage(const std::string& name, int width, int height, int channels, const uint8_t* bytes,
                          const float* floats, bool srgb) {
    CheckImageShape(name, width, height, channels);
    CheckImageMemory("image '" + name + "'", ImageStorageBytes(width, height, channels, bytes != nullptr));
    return AddImage(MakeImage(name, width, height, channels, bytes, floats, srgb));
}

int RenderScene::AddImage(Image image) {
    RequireNotCommitted();
    const uint64_t bytes = ImageStorageBytes(image.width, image.height, image.channels, image.bytes != nullptr);
    CheckImageMemory("image '" + image.name + "'", bytes);
    image_memory_bytes_ += bytes;
    images.push_back(std::move(image));
    return int(images.size()) - 1;
}

void RenderScene::SetImageMemoryLimit(uint64_t bytes) {
    RequireNotCommitted();
    image_memory_limit_ = bytes;
}

void RenderScene::CheckImageMemory(const std::string& image, uint64_t bytes) const {
    if (image_memory_limit_ == 0 || bytes <= image_memory_limit_ - std::min(image_memory_limit_, image_memory_bytes_))
        return;
    throw std::invalid_argument(image + " takes " + GiBText(bytes) + "; with the scene's other images (" +
                                GiBText(image_memory_bytes_) + ") that is more than the " +
                                GiBText(image_memory_limit_) +
                                " the memory limit leaves beside the film: use a smaller image, or raise memory_limit");
}

}  // namespace sphrect::render
