// TODO: implemented by the ErrorStats work item
