// TODO: implemented by the GltfLoader work item
