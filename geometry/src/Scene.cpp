// TODO: implemented by the Scene work item
