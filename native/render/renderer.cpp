// PLACEHOLDER: the renderer (to be written).
namespace sphrect {}
